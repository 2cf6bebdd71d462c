"""Reading TOML tables with precise errors (file, key, line, expected, found).

``tomllib`` reports line numbers for syntax errors only; for the semantic checks
done here :func:`locate_keys` scans the text once and maps every dotted key path
(``body.parts[1].dims``) to the line where it is written, so that an error can
point at it. Arrays of tables are indexed from 0 in key paths.
"""

from __future__ import annotations

import difflib
import math
import re
from collections.abc import Collection, Iterable, Mapping, Sequence
from typing import Any, Literal, overload

from ..errors import InvalidInputError

__all__ = ["ScenarioError", "Table", "locate_keys", "suggest"]


class ScenarioError(InvalidInputError):
    """A scenario file is invalid: names the file, the key, the line, what was
    expected and what was found.

    Attributes
    ----------
    file, key : str
        File name (or ``"<string>"``) and dotted key path (``""`` for the file).
    line : int or None
        1-based line of the key in the file, when known.
    """

    def __init__(self, message: str, *, file: str, key: str = "", line: int | None = None):
        self.file = file
        self.key = key
        self.line = line
        where = file if line is None else f"{file}:{line}"
        what = f" `{key}`" if key else ""
        super().__init__(f"{where}:{what} {message}" if what else f"{where}: {message}")


_HEADER = re.compile(r"^\s*(\[\[?)\s*([^\]]+?)\s*(\]\]?)\s*(#.*)?$")
_KEY = re.compile(
    r"""^\s*((?:[A-Za-z0-9_-]+|"[^"]*"|'[^']*')(?:\s*\.\s*(?:[A-Za-z0-9_-]+|"[^"]*"|'[^']*'))*)\s*="""
)


def _split_dotted(s: str) -> list[str]:
    parts = re.findall(r"""[A-Za-z0-9_-]+|"[^"]*"|'[^']*'""", s)
    return [p[1:-1] if p[:1] in "\"'" else p for p in parts]


def _bracket_delta(line: str) -> int:
    """Net count of ``[``/``{`` minus ``]``/``}`` outside strings and comments."""
    depth = 0
    quote = None
    i = 0
    while i < len(line):
        c = line[i]
        if quote:
            if c == "\\" and quote == '"':
                i += 1
            elif c == quote:
                quote = None
        elif c in "\"'":
            quote = c
        elif c == "#":
            break
        elif c in "[{":
            depth += 1
        elif c in "]}":
            depth -= 1
        i += 1
    return depth


def locate_keys(text: str) -> dict[str, int]:
    """Map dotted key paths to the 1-based line where they are defined (best effort).

    Examples
    --------
    >>> lines = locate_keys("a = 1\\n[body]\\nmass = 2\\n[[body.parts]]\\ndims = [1,\\n 2]\\n")
    >>> lines["a"], lines["body"], lines["body.mass"], lines["body.parts[0].dims"]
    (1, 2, 3, 5)
    """
    where: dict[str, int] = {}
    counts: dict[str, int] = {}
    prefix = ""
    depth = 0
    for n, line in enumerate(text.splitlines(), start=1):
        if depth > 0:  # inside a multi-line array or inline table
            depth += _bracket_delta(line)
            continue
        m = _HEADER.match(line)
        if m and _KEY.match(line) is None:
            keys = _split_dotted(m.group(2))
            # resolve array-of-tables indices of the enclosing tables
            path = ""
            for k in keys[:-1]:
                path = f"{path}.{k}" if path else k
                if path in counts:
                    path = f"{path}[{counts[path] - 1}]"
            last = f"{path}.{keys[-1]}" if path else keys[-1]
            if m.group(1) == "[[":
                counts[last] = counts.get(last, 0) + 1
                where.setdefault(last, n)
                last = f"{last}[{counts[last] - 1}]"
            where.setdefault(last, n)
            prefix = last
            continue
        m = _KEY.match(line)
        if m:
            path = prefix
            for k in _split_dotted(m.group(1)):
                path = f"{path}.{k}" if path else k
                where.setdefault(path, n)
            depth = _bracket_delta(line[m.end() :])
    return where


def suggest(word: str, valid: Iterable[str]) -> list[str]:
    """The closest valid word (difflib), or one that is a prefix of ``word`` or has it as
    prefix (``quaternion`` -> ``quat``); empty if none is close.

    >>> suggest("duraton", ["duration", "step"]), suggest("quaternion", ["quat", "euler"])
    (['duration'], ['quat'])
    """
    valid = list(valid)
    hint = difflib.get_close_matches(word, valid, n=1, cutoff=0.6)
    if hint:
        return hint
    low = word.lower()
    pref = [
        v
        for v in valid
        if min(len(v), len(low)) >= 3 and (low.startswith(v.lower()) or v.lower().startswith(low))
    ]
    return pref[:1]


def _describe(value: Any) -> str:
    if isinstance(value, bool):
        return f"{str(value).lower()} (a boolean)"
    if isinstance(value, str):
        return f"{value!r} (a string)"
    if isinstance(value, int | float):
        return f"{value!r} (a number)"
    if isinstance(value, Mapping):
        return "a table"
    if isinstance(value, list):
        text = repr(value)
        if len(text) > 60:
            text = text[:57] + "..."
        return f"{text} (an array of {len(value)})"
    return f"{value!r}"


def _is_number(x: Any) -> bool:
    return isinstance(x, int | float) and not isinstance(x, bool)


class Table:
    """A TOML table being read: every key taken is recorded, the rest are errors.

    ``path`` is the dotted path of the table, ``file`` the file name and
    ``lines`` the map from :func:`locate_keys`.
    """

    def __init__(self, data: Mapping[str, Any], path: str, file: str, lines: Mapping[str, int]):
        self.data = data
        self.path = path
        self.file = file
        self.lines = lines
        self._used: set[str] = set()

    # -- errors ---------------------------------------------------------------------------
    def key_path(self, key: str) -> str:
        return f"{self.path}.{key}" if self.path else key

    def error(self, key: str | None, message: str) -> ScenarioError:
        path = self.path if key is None else self.key_path(key)
        line = self.lines.get(path)
        if line is None and self.path:
            line = self.lines.get(self.path)
        return ScenarioError(message, file=self.file, key=path, line=line)

    def expected(self, key: str, expected: str, value: Any) -> ScenarioError:
        return self.error(key, f"expected {expected}, found {_describe(value)}.")

    # -- access ---------------------------------------------------------------------------
    def has(self, key: str) -> bool:
        return key in self.data

    def raw(self, key: str, default: Any = None) -> Any:
        self._used.add(key)
        return self.data.get(key, default)

    def require(self, key: str, expected: str) -> Any:
        if key not in self.data:
            raise self.error(None, f"missing key `{key}`: expected {expected}.")
        return self.raw(key)

    # The overloads tell the type checker that a required key or a default gives a value.
    @overload
    def number(
        self,
        key: str,
        default: float,
        *,
        positive: bool = ...,
        nonnegative: bool = ...,
        required: bool = ...,
    ) -> float: ...
    @overload
    def number(
        self,
        key: str,
        default: None = None,
        *,
        positive: bool = ...,
        nonnegative: bool = ...,
        required: Literal[True],
    ) -> float: ...
    @overload
    def number(
        self,
        key: str,
        default: float | None = None,
        *,
        positive: bool = ...,
        nonnegative: bool = ...,
        required: bool = ...,
    ) -> float | None: ...
    def number(
        self,
        key: str,
        default: float | None = None,
        *,
        positive: bool = False,
        nonnegative: bool = False,
        required: bool = False,
    ) -> float | None:
        what = (
            "a positive number"
            if positive
            else ("a non-negative number" if nonnegative else "a number")
        )
        if key not in self.data:
            if required:
                raise self.error(None, f"missing key `{key}`: expected {what}.")
            self._used.add(key)
            return default
        v = self.raw(key)
        if not _is_number(v) or not math.isfinite(v):
            raise self.expected(key, f"{what}", v)
        if (positive and v <= 0) or (nonnegative and v < 0):
            raise self.expected(key, what, v)
        return float(v)

    @overload
    def integer(
        self, key: str, default: int, *, minimum: int = ..., required: bool = ...
    ) -> int: ...
    @overload
    def integer(
        self, key: str, default: None = None, *, minimum: int = ..., required: Literal[True]
    ) -> int: ...
    @overload
    def integer(
        self, key: str, default: int | None = None, *, minimum: int = ..., required: bool = ...
    ) -> int | None: ...
    def integer(
        self, key: str, default: int | None = None, *, minimum: int = 1, required: bool = False
    ) -> int | None:
        what = f"an integer >= {minimum}"
        if key not in self.data:
            if required:
                raise self.error(None, f"missing key `{key}`: expected {what}.")
            self._used.add(key)
            return default
        v = self.raw(key)
        if isinstance(v, bool) or not isinstance(v, int) or v < minimum:
            raise self.expected(key, what, v)
        return v

    @overload
    def boolean(self, key: str, default: bool, *, required: bool = ..., why: str = ...) -> bool: ...
    @overload
    def boolean(
        self, key: str, default: None = None, *, required: Literal[True], why: str = ...
    ) -> bool: ...
    @overload
    def boolean(
        self, key: str, default: bool | None = None, *, required: bool = ..., why: str = ...
    ) -> bool | None: ...
    def boolean(
        self, key: str, default: bool | None = None, *, required: bool = False, why: str = ""
    ) -> bool | None:
        if key not in self.data:
            if required:
                raise self.error(None, f"missing key `{key}`: expected true or false{why}.")
            self._used.add(key)
            return default
        v = self.raw(key)
        if not isinstance(v, bool):
            raise self.expected(key, "true or false", v)
        return v

    @overload
    def string(
        self,
        key: str,
        default: str,
        *,
        choices: Collection[str] | None = ...,
        required: bool = ...,
    ) -> str: ...
    @overload
    def string(
        self,
        key: str,
        default: None = None,
        *,
        choices: Collection[str] | None = ...,
        required: Literal[True],
    ) -> str: ...
    @overload
    def string(
        self,
        key: str,
        default: str | None = None,
        *,
        choices: Collection[str] | None = ...,
        required: bool = ...,
    ) -> str | None: ...
    def string(
        self,
        key: str,
        default: str | None = None,
        *,
        choices: Collection[str] | None = None,
        required: bool = False,
    ) -> str | None:
        what = "a string" if choices is None else "one of " + ", ".join(f'"{c}"' for c in choices)
        if key not in self.data:
            if required:
                raise self.error(None, f"missing key `{key}`: expected {what}.")
            self._used.add(key)
            return default
        v = self.raw(key)
        if not isinstance(v, str):
            raise self.expected(key, what, v)
        if choices is not None and v not in choices:
            hint = suggest(v, list(choices))
            extra = f' Did you mean "{hint[0]}"?' if hint else ""
            raise self.error(key, f"expected {what}, found {v!r}.{extra}")
        return v

    @overload
    def vector(
        self,
        key: str,
        n: int | None = ...,
        *,
        required: Literal[True] = ...,
        default: None = None,
        what: str | None = ...,
    ) -> tuple[float, ...]: ...
    @overload
    def vector(
        self,
        key: str,
        n: int | None = ...,
        *,
        required: bool = ...,
        default: tuple[float, ...],
        what: str | None = ...,
    ) -> tuple[float, ...]: ...
    @overload
    def vector(
        self,
        key: str,
        n: int | None = ...,
        *,
        required: bool = ...,
        default: tuple[float, ...] | None = None,
        what: str | None = ...,
    ) -> tuple[float, ...] | None: ...
    def vector(
        self,
        key: str,
        n: int | None = 3,
        *,
        required: bool = True,
        default: tuple[float, ...] | None = None,
        what: str | None = None,
    ) -> tuple[float, ...] | None:
        desc = what or (f"an array of {n} numbers" if n else "an array of numbers")
        if key not in self.data:
            if required:
                raise self.error(None, f"missing key `{key}`: expected {desc}.")
            self._used.add(key)
            return default
        v = self.raw(key)
        if (
            not isinstance(v, list)
            or (n is not None and len(v) != n)
            or not v
            or not all(_is_number(x) and math.isfinite(x) for x in v)
        ):
            raise self.expected(key, desc, v)
        return tuple(float(x) for x in v)

    def matrix(
        self, key: str, rows: int | None, cols: int, *, what: str | None = None
    ) -> tuple[tuple[float, ...], ...]:
        desc = what or (
            f"a {rows}x{cols} array of numbers (a list of rows)"
            if rows
            else f"an array of rows of {cols} numbers"
        )
        v = self.raw(key)
        ok = (
            isinstance(v, list)
            and v
            and (rows is None or len(v) == rows)
            and all(
                isinstance(r, list)
                and len(r) == cols
                and all(_is_number(x) and math.isfinite(x) for x in r)
                for r in v
            )
        )
        if not ok:
            raise self.expected(key, desc, v)
        return tuple(tuple(float(x) for x in r) for r in v)

    @overload
    def table(self, key: str, *, required: Literal[True]) -> Table: ...
    @overload
    def table(self, key: str, *, required: bool = ...) -> Table | None: ...
    def table(self, key: str, *, required: bool = False) -> Table | None:
        if key not in self.data:
            if required:
                raise self.error(None, f"missing table `[{self.key_path(key)}]`.")
            self._used.add(key)
            return None
        v = self.raw(key)
        if not isinstance(v, Mapping):
            raise self.expected(key, "a table", v)
        return Table(v, self.key_path(key), self.file, self.lines)

    def tables(self, key: str) -> list[Table]:
        v = self.raw(key)
        if not isinstance(v, list) or not v or not all(isinstance(x, Mapping) for x in v):
            raise self.expected(key, f"an array of tables ([[{self.key_path(key)}]])", v)
        return [
            Table(x, f"{self.key_path(key)}[{i}]", self.file, self.lines) for i, x in enumerate(v)
        ]

    @overload
    def exclusive(
        self, keys: Sequence[str], *, required: Literal[True] = ..., what: str = ...
    ) -> str: ...
    @overload
    def exclusive(
        self, keys: Sequence[str], *, required: bool = ..., what: str = ...
    ) -> str | None: ...
    def exclusive(
        self, keys: Sequence[str], *, required: bool = True, what: str = ""
    ) -> str | None:
        """The one key of ``keys`` present (error if several, or none and required)."""
        present = [k for k in keys if k in self.data]
        if len(present) > 1:
            raise self.error(
                present[1],
                f"conflicts with `{self.key_path(present[0])}`: "
                f"give only one of {', '.join(f'`{k}`' for k in keys)}.",
            )
        if not present:
            if required:
                raise self.error(
                    None,
                    "missing key: expected one of "
                    + ", ".join(f"`{k}`" for k in keys)
                    + (f" ({what})" if what else "")
                    + ".",
                )
            return None
        return present[0]

    def forbid(self, keys: Iterable[str], reason: str) -> None:
        for k in keys:
            if k in self.data:
                raise self.error(k, f"not allowed here: {reason}.")

    def known(self, allowed: Iterable[str]) -> None:
        """Raise on the first key not in ``allowed`` (checked before reading, so that a
        misspelt required key is reported as a typo rather than as missing)."""
        self.finish(allowed, only_unknown=True)

    def finish(self, allowed: Iterable[str] | None = None, *, only_unknown: bool = False) -> None:
        """Raise on the first key that was never taken (a typo), suggesting the closest."""
        valid = sorted(set(allowed) if allowed is not None else self._used)
        for key in self.data:
            if key not in (valid if only_unknown else self._used):
                hint = suggest(key, valid)
                extra = f" Did you mean `{hint[0]}`?" if hint else ""
                listing = ", ".join(f"`{k}`" for k in valid) if valid else "none"
                raise self.error(key, f"unknown key.{extra} Valid keys here: {listing}.")
