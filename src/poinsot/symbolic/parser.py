"""A whitelist parser for formulas read from untrusted text (scenario files).

:func:`parse_expression` turns a string such as ``"m*l**2*theta_dot**2/2"`` into a
SymPy expression **without evaluating any code**: the text is parsed by Python's
:mod:`ast` module (which only builds a syntax tree) and the tree is walked
against a whitelist:

- numbers (integers and decimals; no complex, booleans or strings),
- the names the caller declared, and the constant ``pi``,
- the operators ``+ - * / **`` and unary ``+``/``-``,
- calls, with positional arguments only, of the functions in :data:`FUNCTIONS`.

Everything else (attribute access, subscripts, lambdas, comprehensions,
comparisons, keywords, names starting with ``_`` such as ``__import__``...) is
rejected with an :class:`ExpressionError` that names the offending token and its
column. Neither :func:`eval`, :func:`exec` nor :func:`sympy.sympify` ever sees the
text. Limits bound the work a hostile string can cause: its length
(:data:`MAX_LENGTH`), the depth of its syntax tree (:data:`MAX_DEPTH`), and the
size of powers of numbers (``9**9**9`` is refused before SymPy computes it, see
:data:`MAX_POWER_DIGITS`). The safety rules are listed in ``docs/lagrange.md``.
"""

from __future__ import annotations

import ast
import math
from collections.abc import Mapping, Sequence
from typing import Any

from ..errors import InvalidInputError, InvalidTypeError

__all__ = [
    "parse_expression",
    "ExpressionError",
    "FUNCTIONS",
    "MAX_LENGTH",
    "MAX_DEPTH",
    "MAX_EXPONENT",
    "MAX_POWER_DIGITS",
]

#: Longest accepted expression text (characters).
MAX_LENGTH = 4000
#: Deepest accepted syntax tree (nested operations and calls).
MAX_DEPTH = 64
#: Largest ``|n|`` accepted in ``x**n`` when ``n`` is a number.
MAX_EXPONENT = 1000
#: Largest number of decimal digits of a power of two numbers (``10**400`` is refused).
MAX_POWER_DIGITS = 300

#: Functions an expression may call: name -> (SymPy function name, number of arguments).
FUNCTIONS: Mapping[str, tuple[str, int]] = {
    "sin": ("sin", 1),
    "cos": ("cos", 1),
    "tan": ("tan", 1),
    "cot": ("cot", 1),
    "asin": ("asin", 1),
    "acos": ("acos", 1),
    "atan": ("atan", 1),
    "atan2": ("atan2", 2),
    "sinh": ("sinh", 1),
    "cosh": ("cosh", 1),
    "tanh": ("tanh", 1),
    "exp": ("exp", 1),
    "log": ("log", 1),
    "sqrt": ("sqrt", 1),
    "abs": ("Abs", 1),
    "sign": ("sign", 1),
}

#: Names that mean a constant unless the caller declares them.
_CONSTANTS = ("pi",)

_BINOPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**"}
_UNARY = {ast.USub: "-", ast.UAdd: "+"}


class ExpressionError(InvalidInputError):
    """An expression string was rejected by :func:`parse_expression`.

    Attributes
    ----------
    text : str
        The expression.
    token : str
        The offending token (e.g. ``"__import__"``, ``".system"``, ``"lambda"``).
    column : int or None
        1-based column of the token in ``text`` (None when unknown).
    """

    def __init__(
        self, message: str, *, text: str = "", token: str = "", column: int | None = None
    ) -> None:
        super().__init__(message)
        self.text = text
        self.token = token
        self.column = column


def _declared(symbols: object) -> dict[str, Any]:
    import sympy

    if symbols is None:
        return {}
    if isinstance(symbols, Mapping):
        items = list(symbols.items())
    elif isinstance(symbols, str):
        raise InvalidTypeError(
            "Expected `symbols` to be a mapping of names to SymPy objects or a sequence of "
            f"SymPy symbols, got the string {symbols!r}."
        )
    elif isinstance(symbols, Sequence):
        items = []
        for s in symbols:
            if not isinstance(s, sympy.Basic):
                raise InvalidTypeError(
                    f"Expected `symbols` to hold SymPy symbols, got {type(s).__name__} {s!r}."
                )
            name = getattr(s, "name", None) or getattr(getattr(s, "func", None), "__name__", "")
            items.append((str(name), s))
    else:
        raise InvalidTypeError(
            f"Expected `symbols` to be a mapping or a sequence, got {type(symbols).__name__}."
        )
    out: dict[str, Any] = {}
    for name, value in items:
        if not isinstance(name, str) or not name.isidentifier() or name.startswith("_"):
            raise InvalidInputError(
                f"Expected every name in `symbols` to be an identifier not starting with '_', "
                f"got {name!r}."
            )
        if name in FUNCTIONS:
            raise InvalidInputError(
                f"Expected the names in `symbols` to differ from the function names, got {name!r}."
            )
        if isinstance(value, int | float) and not isinstance(value, bool):
            value = sympy.sympify(value)  # a number, never a string
        if not isinstance(value, sympy.Basic):
            raise InvalidTypeError(
                f"Expected `symbols[{name!r}]` to be a SymPy object or a number, "
                f"got {type(value).__name__}."
            )
        out[name] = value
    return out


def _token(text: str, node: ast.AST) -> tuple[str, int | None]:
    """The source text of ``node`` (first line, shortened) and its 1-based column."""
    seg = ast.get_source_segment(text, node) or type(node).__name__
    seg = seg.splitlines()[0] if seg else seg
    if len(seg) > 40:
        seg = seg[:37] + "..."
    col = getattr(node, "col_offset", None)
    return seg, None if col is None else col + 1


class _Builder:
    def __init__(self, text: str, names: dict[str, Any]) -> None:
        import sympy

        self.sp = sympy
        self.text = text
        self.names = names

    def fail(self, what: str, node: ast.AST, token: str | None = None) -> ExpressionError:
        tok, col = _token(self.text, node)
        tok = token if token is not None else tok
        where = f" at column {col}" if col is not None else ""
        shown = self.text if len(self.text) <= 80 else self.text[:77] + "..."
        return ExpressionError(
            f"{what}: {tok!r}{where} in expression {shown!r}.",
            text=self.text,
            token=tok,
            column=col,
        )

    def build(self, node: ast.AST, depth: int = 1) -> Any:
        if depth > MAX_DEPTH:
            raise self.fail(f"expression nested deeper than {MAX_DEPTH} levels", node)
        sp = self.sp
        if isinstance(node, ast.Constant):
            v = node.value
            if isinstance(v, bool) or not isinstance(v, int | float):
                raise self.fail("only real numbers are allowed as constants", node)
            if isinstance(v, float):
                if not math.isfinite(v):
                    raise self.fail("number out of the floating-point range", node)
                return sp.Rational(repr(v))  # the decimal the user wrote, exactly
            return sp.Integer(v)
        if isinstance(node, ast.Name):
            name = node.id
            if name.startswith("_"):
                raise self.fail("names starting with '_' are not allowed", node)
            if name in self.names:
                return self.names[name]
            if name in _CONSTANTS:
                return sp.pi
            if name in FUNCTIONS:
                raise self.fail(f"function {name!r} used without a call", node)
            declared = ", ".join(sorted(self.names)) or "none"
            raise self.fail(f"unknown name (declared: {declared})", node)
        if isinstance(node, ast.UnaryOp):
            if type(node.op) not in _UNARY:
                raise self.fail("operator not allowed (only unary + and -)", node)
            arg = self.build(node.operand, depth + 1)
            return -arg if isinstance(node.op, ast.USub) else arg
        if isinstance(node, ast.BinOp):
            op = _BINOPS.get(type(node.op))
            if op is None:
                sym = {ast.Mod: "%", ast.FloorDiv: "//", ast.MatMult: "@", ast.BitXor: "^"}
                raise self.fail(
                    "operator not allowed (only + - * / **)",
                    node,
                    sym.get(type(node.op), type(node.op).__name__),
                )
            a = self.build(node.left, depth + 1)
            b = self.build(node.right, depth + 1)
            if op == "+":
                return a + b
            if op == "-":
                return a - b
            if op == "*":
                return a * b
            if op == "/":
                if b == 0:
                    raise self.fail("division by zero", node)
                return a / b
            return self.power(a, b, node)
        if isinstance(node, ast.Call):
            if not isinstance(node.func, ast.Name):
                raise self.fail("only calls of the allowed functions by name are allowed", node)
            fname = node.func.id
            if fname.startswith("_"):
                raise self.fail("names starting with '_' are not allowed", node.func, fname)
            if fname not in FUNCTIONS:
                allowed = ", ".join(FUNCTIONS)
                raise self.fail(f"function not allowed (allowed: {allowed})", node.func, fname)
            if node.keywords:
                raise self.fail("keyword arguments are not allowed", node.keywords[0], None)
            spname, nargs = FUNCTIONS[fname]
            if any(isinstance(a, ast.Starred) for a in node.args):
                raise self.fail("starred arguments are not allowed", node)
            if len(node.args) != nargs:
                raise self.fail(
                    f"function {fname!r} takes {nargs} argument(s), got {len(node.args)}", node
                )
            args = [self.build(a, depth + 1) for a in node.args]
            return getattr(sp, spname)(*args)
        what = {
            ast.Attribute: "attribute access is not allowed",
            ast.Subscript: "subscripts are not allowed",
            ast.Lambda: "lambdas are not allowed",
            ast.Compare: "comparisons are not allowed",
            ast.BoolOp: "boolean operators are not allowed",
            ast.IfExp: "conditional expressions are not allowed",
            ast.NamedExpr: "assignments are not allowed",
            ast.JoinedStr: "strings are not allowed",
        }.get(type(node), f"syntax not allowed ({type(node).__name__})")
        tok: str | None = None
        if isinstance(node, ast.Attribute):
            tok = "." + node.attr
        elif isinstance(node, ast.Lambda):
            tok = "lambda"
        raise self.fail(what, node, tok)

    def power(self, a: Any, b: Any, node: ast.AST) -> Any:
        sp = self.sp
        if b.is_Number:
            if not b.is_real or abs(b) > MAX_EXPONENT:
                raise self.fail(f"exponent larger than {MAX_EXPONENT} in absolute value", node)
            if a.is_Number and a != 0:
                digits = abs(float(b)) * abs(math.log10(abs(float(sp.N(a, 20)))))
                if digits > MAX_POWER_DIGITS:
                    raise self.fail(
                        f"power of numbers with more than {MAX_POWER_DIGITS} digits", node
                    )
        elif a.is_Number and abs(a) != 1 and b.is_number:
            # e.g. 2**(pi*100): a number raised to a non-literal numeric exponent
            if abs(float(sp.N(b, 20))) > MAX_EXPONENT:
                raise self.fail(f"exponent larger than {MAX_EXPONENT} in absolute value", node)
        return a**b


def parse_expression(text: str, symbols: Mapping[str, Any] | Sequence[Any] | None = None) -> Any:
    """Parse an untrusted formula into a SymPy expression, without running any code.

    Parameters
    ----------
    text : str
        The formula in Python syntax, e.g. ``"m*(l*theta_dot)**2/2"``. At most
        :data:`MAX_LENGTH` characters.
    symbols : mapping of str to SymPy object, or sequence of SymPy symbols, optional
        The names the formula may use and what they stand for (a symbol, a
        ``dynamicsymbols`` function, a number...). A sequence of symbols declares
        each under its own name. ``pi`` is the constant unless declared.

    Returns
    -------
    sympy.Expr
        The expression. Decimal literals become exact rationals (``0.5`` -> ``1/2``).

    Raises
    ------
    ExpressionError
        (an :class:`~poinsot.errors.InvalidInputError`) naming the offending token
        and its column: syntax errors, undeclared names, names starting with ``_``,
        attribute access, subscripts, lambdas, comparisons, keyword arguments,
        calls of functions not in :data:`FUNCTIONS`, exponents above
        :data:`MAX_EXPONENT`, powers of numbers above :data:`MAX_POWER_DIGITS`
        digits, trees deeper than :data:`MAX_DEPTH`, texts longer than
        :data:`MAX_LENGTH`.
    InvalidTypeError
        If ``text`` is not a string.

    Notes
    -----
    The text is only ever given to :func:`ast.parse`; the tree is checked node by
    node against the whitelist in the module docstring and translated to SymPy
    operations directly (never :func:`eval`, :func:`exec` or
    :func:`sympy.sympify`). Used for the scenario kind ``lagrangian``
    (``docs/lagrange.md``; the mechanics is ``docs/theory.md §11``).

    Examples
    --------
    >>> import sympy
    >>> m, x = sympy.symbols("m x")
    >>> parse_expression("m*x**2/2 + 0.5*sin(x)", {"m": m, "x": x})
    m*x**2/2 + sin(x)/2
    >>> try:
    ...     parse_expression("__import__('os')", {"x": x})
    ... except ExpressionError as exc:
    ...     print(exc.token, exc.column)
    __import__ 1
    """
    if not isinstance(text, str):
        raise InvalidTypeError(
            f"Expected the expression to be a string, got {type(text).__name__}."
        )
    if len(text) > MAX_LENGTH:
        raise ExpressionError(
            f"Expected an expression of at most {MAX_LENGTH} characters, got {len(text)}.",
            text=text[:40],
            token=text[:20],
        )
    names = _declared(symbols)
    text = " ".join(text.split())  # formulas may span lines (TOML multi-line strings)
    if not text:
        raise ExpressionError("Expected a non-empty expression, got an empty string.", text=text)
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        col = exc.offset
        line = (exc.text or text).rstrip("\n")
        tok = line[col - 1 : col + 9].split()[0] if col and 0 < col <= len(line) else ""
        if tok.startswith("_"):
            msg = "names starting with '_' are not allowed"
        else:
            msg = f"invalid syntax ({exc.msg})"
        raise ExpressionError(
            f"{msg}: {tok!r} at column {col} in expression {text!r}.",
            text=text,
            token=tok,
            column=col,
        ) from None
    except (RecursionError, MemoryError, ValueError) as exc:
        raise ExpressionError(
            f"expression too complex to parse ({type(exc).__name__}): {text[:40]!r}.",
            text=text,
        ) from None
    builder = _Builder(text.strip(), names)
    # the most dangerous tokens first, leftmost first: private names, attributes, lambdas
    worst: list[tuple[int, str, ast.AST, str | None]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and node.id.startswith("_"):
            worst.append((node.col_offset, "names starting with '_' are not allowed", node, None))
        elif isinstance(node, ast.Attribute):
            col = node.value.end_col_offset or 0
            worst.append((col, "attribute access is not allowed", node, "." + node.attr))
        elif isinstance(node, ast.Lambda):
            worst.append((node.col_offset, "lambdas are not allowed", node, "lambda"))
    if worst:
        _, what, node, first_tok = min(worst, key=lambda w: w[0])
        raise builder.fail(what, node, first_tok)
    return builder.build(tree.body)
