"""The example notebooks of docs/notebooks run top to bottom (issue 21).

Each notebook is executed by nbclient in a real Jupyter kernel of this Python (with
this checkout's poinsot on its path), every cell with a time limit; any error fails
the test. The notebooks assert their own results against independent truths (SciPy's
rotations, SymPy's LagrangesMethod, the exact solutions, normal modes), so a notebook
that runs is a notebook that is right. Stored without outputs.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat", reason="the notebooks need poinsot[notebook]")
nbclient = pytest.importorskip("nbclient", reason="the notebooks need poinsot[notebook]")
pytest.importorskip("ipykernel", reason="the notebooks need poinsot[notebook]")

NOTEBOOKS = sorted((Path(__file__).resolve().parents[1] / "docs" / "notebooks").glob("*.ipynb"))


def test_there_are_four_notebooks_stored_without_outputs():
    names = {p.stem for p in NOTEBOOKS}
    assert {"rotations", "free_body", "heavy_top", "lagrange"} <= names
    for p in NOTEBOOKS:
        nb = nbformat.read(p, as_version=4)
        assert all(not c.get("outputs") for c in nb.cells if c.cell_type == "code"), p.name


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_runs(path, tmp_path, monkeypatch):
    src = str(Path(__file__).resolve().parents[1] / "src")
    monkeypatch.setenv("PYTHONPATH", src + os.pathsep + os.environ.get("PYTHONPATH", ""))
    # Jupyter's own inline backend (Agg would draw nothing and let a broken figure pass):
    # every figure a cell makes must arrive as a PNG output (issue 38)
    monkeypatch.setenv("MPLBACKEND", "module://matplotlib_inline.backend_inline")
    nb = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(
        nb, timeout=120, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}
    )
    client.execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    assert any(o.output_type in ("display_data", "execute_result") for o in outputs)
    for i, cell in enumerate(nb.cells):
        if cell.cell_type == "code" and re.search(_MAKES_FIGURE, cell.source):
            pngs = [o for o in cell.outputs if "image/png" in o.get("data", {})]
            assert pngs, f"{path.name}, cell {i}: makes a figure but shows none"


#: matplotlib calls that make a figure in a cell (the notebooks draw through pyplot or
#: poinsot's plot_* functions)
_MAKES_FIGURE = r"plt\.(subplots|figure)\(|\bplot_\w+\("
