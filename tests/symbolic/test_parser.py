"""The whitelist expression parser: what it accepts (checked against SymPy built by
hand) and every way a hostile string is refused without running anything."""

from __future__ import annotations

import os

import pytest

sympy = pytest.importorskip("sympy")

from poinsot.errors import InvalidInputError, InvalidTypeError  # noqa: E402
from poinsot.symbolic import (  # noqa: E402
    MAX_DEPTH,
    MAX_LENGTH,
    ExpressionError,
    parse_expression,
)

m, x, th = sympy.symbols("m x theta")
SYMS = {"m": m, "x": x, "theta": th}


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("m*x**2/2", m * x**2 / 2),
        ("-x + +x - (x - 1)", 1 - x),
        ("0.5*m*x**2", m * x**2 / 2),  # decimals are exact rationals
        ("sin(theta)**2 + cos(theta)**2", sympy.sin(th) ** 2 + sympy.cos(th) ** 2),
        (
            "atan2(x, m) + sqrt(x) + exp(-x) + log(m) + abs(x)",
            sympy.atan2(x, m) + sympy.sqrt(x) + sympy.exp(-x) + sympy.log(m) + sympy.Abs(x),
        ),
        ("2*pi*x", 2 * sympy.pi * x),
        ("x**-2", x**-2),
        ("1e-3*x", x / 1000),
        ("  x  ", x),
    ],
)
def test_accepted_expressions_match_sympy(text, expected):
    assert sympy.simplify(parse_expression(text, SYMS) - expected) == 0


def test_sequence_of_symbols_declares_their_names():
    assert parse_expression("x*m", [x, m]) == x * m


def test_declared_name_shadows_pi():
    p = sympy.Symbol("p")
    assert parse_expression("pi + 1", {"pi": p}) == p + 1


@pytest.mark.parametrize(
    ("text", "token"),
    [
        ("__import__('os').system('touch HACKED')", "__import__"),
        ("x.__class__", ".__class__"),
        ("x.real", ".real"),
        ("(lambda: 1)()", "lambda"),
        ("lambda x: x", "lambda"),
        ("__builtins__", "__builtins__"),
        ("_x + 1", "_x"),
        ("open('f', 'w')", "open"),
        ("eval('1')", "eval"),
        ("exec('1')", "exec"),
        ("getattr(x, 'y')", "getattr"),
        ("x[0]", "x[0]"),
        ("[x for x in m]", "[x for x in m]"),
        ("x if m else 1", "x if m else 1"),
        ("x < 1", "x < 1"),
        ("x and m", "x and m"),
        ("(y := 1)", "y := 1"),
        ("'abc'", "'abc'"),
        ("1j*x", "1j"),
        ("True*x", "True"),
        ("x % 2", "%"),
        ("x // 2", "//"),
        ("x ^ 2", "^"),
        ("sin(x, y=1)", "y=1"),
        ("sin(*[x])", "sin(*[x])"),
        ("sin(x, m)", "sin(x, m)"),
        ("y + x", "y"),
        ("sin", "sin"),
        ("9**9**9", "9**9**9"),
        ("x**100000", "x**100000"),
        ("10**400", "10**400"),
        ("2**(pi*1000)", "2**(pi*1000)"),
        ("1e999", "1e999"),
        ("x/0", "x/0"),
        ("x +* 2", "*"),
        ("", ""),
    ],
)
def test_malicious_or_invalid_strings_are_refused_naming_the_token(text, token):
    with pytest.raises(ExpressionError) as info:
        parse_expression(text, SYMS)
    assert info.value.token == token
    if token:
        assert repr(token) in str(info.value)
    assert isinstance(info.value, InvalidInputError)


def test_nothing_runs(tmp_path, monkeypatch):
    """Strings that would create a file if evaluated leave the directory empty."""
    monkeypatch.chdir(tmp_path)
    target = tmp_path / "HACKED"
    attacks = [
        f"__import__('os').system('touch {target}')",
        f"open('{target}', 'w').write('x')",
        f"(lambda: __import__('pathlib').Path('{target}').touch())()",
        f"x.__class__.__mro__[1].__subclasses__() or open('{target}', 'w')",
        f"sin(__import__('os').system('touch {target}'))",
        "().__class__.__bases__[0].__subclasses__()",
    ]
    for text in attacks:
        with pytest.raises(ExpressionError):
            parse_expression(text, SYMS)
    assert not target.exists()
    assert os.listdir(tmp_path) == []


def test_limits_length_and_depth():
    with pytest.raises(ExpressionError, match=f"at most {MAX_LENGTH} characters"):
        parse_expression("x+" * MAX_LENGTH + "x", SYMS)
    deep = "sin(" * (MAX_DEPTH + 1) + "x" + ")" * (MAX_DEPTH + 1)
    with pytest.raises(ExpressionError, match="nested deeper"):
        parse_expression(deep, SYMS)
    with pytest.raises(ExpressionError):
        parse_expression("-" * (MAX_LENGTH - 1) + "x", SYMS)
    with pytest.raises(ExpressionError):
        parse_expression("(" * 300 + "x" + ")" * 300, SYMS)
    ok = "sin(" * (MAX_DEPTH // 2) + "x" + ")" * (MAX_DEPTH // 2)
    assert parse_expression(ok, SYMS).has(sympy.sin)


def test_bad_arguments():
    with pytest.raises(InvalidTypeError, match="string"):
        parse_expression(3, SYMS)
    with pytest.raises(InvalidInputError, match="'_m'"):
        parse_expression("x", {"_m": m})
    with pytest.raises(InvalidInputError, match="'sin'"):
        parse_expression("x", {"sin": m})
    with pytest.raises(InvalidTypeError, match="SymPy"):
        parse_expression("x", {"x": "os.system"})
    with pytest.raises(InvalidTypeError, match="string"):
        parse_expression("x", "x")


def test_column_is_reported():
    with pytest.raises(ExpressionError) as info:
        parse_expression("m*x + y", SYMS)
    assert info.value.column == 7
    assert "column 7" in str(info.value)
