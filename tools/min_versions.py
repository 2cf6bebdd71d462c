"""Print pip constraints pinning the core dependencies to their minimum versions.

Reads ``[project] dependencies`` of ``pyproject.toml`` and prints one line
``name==X.Y`` per requirement with a lower bound ``>=X.Y``, so that ``make
test-min`` can install NumPy, SciPy and numba at exactly the oldest versions the
package claims to support. The optional extras are left free (pip picks versions
that declare support for the pinned NumPy), except the packages in
``ABI_TIED``: their wheels are built for one NumPy major version without saying
so in their metadata (recent pyarrow refuses NumPy 1.x at import), so they are
pinned to the minimum their extra allows as well::

    python tools/min_versions.py > constraints.txt
    pip install -c constraints.txt -e ".[all]"
"""

from __future__ import annotations

import re
import sys
import tomllib
from pathlib import Path

#: Optional dependencies whose newest wheels need a newer NumPy than their metadata says.
ABI_TIED = {"pyarrow"}

_REQ = re.compile(r"^\s*([A-Za-z0-9_.\-]+)\s*(?:\[[^\]]*\])?\s*(.*)$")


def minimum_pins(pyproject: Path) -> list[str]:
    """``name==minimum`` for every core dependency that has a ``>=`` bound."""
    data = tomllib.loads(pyproject.read_text(encoding="utf-8"))
    project = data["project"]
    extras = [r for reqs in project.get("optional-dependencies", {}).values() for r in reqs]
    tied = [r for r in extras if _REQ.match(r) and _REQ.match(r).group(1).lower() in ABI_TIED]
    pins = []
    for req in [*project.get("dependencies", []), *tied]:
        req = req.split(";")[0]
        match = _REQ.match(req)
        if match is None:
            continue
        name, spec = match.groups()
        lower = re.search(r">=\s*([0-9][0-9A-Za-z.]*)", spec)
        if lower and f"{name}=={lower.group(1)}" not in pins:
            pins.append(f"{name}=={lower.group(1)}")
    return pins


def main(argv: list[str]) -> int:
    root = Path(__file__).resolve().parents[1]
    path = Path(argv[0]) if argv else root / "pyproject.toml"
    print("\n".join(minimum_pins(path)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
