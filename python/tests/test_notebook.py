"""The example notebook (python/examples/open_a_run.ipynb), executed by nbclient in a
Python kernel of this environment, its printed figures checked against the run it
made, opened again here."""

import re
from pathlib import Path

import nbformat
import numpy as np
from nbclient import NotebookClient

import areo
from test_areo import ROOT

NOTEBOOK = ROOT / "python/examples/open_a_run.ipynb"


def text_of(cell):
    return "".join(
        o.get("text", "") if o["output_type"] == "stream" else o.get("data", {}).get("text/plain", "")
        for o in cell.get("outputs", [])
    )


def test_the_notebook_opens_a_run_and_draws_it():
    nb = nbformat.read(NOTEBOOK, as_version=4)
    client = NotebookClient(nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(NOTEBOOK.parent)}})
    client.execute()
    code = [c for c in nb.cells if c.cell_type == "code"]
    errors = [o for c in code for o in c.outputs if o["output_type"] == "error"]
    assert not errors, errors
    first, plan, dem, shadows = (text_of(c) for c in code[:4])
    run = areo.open(Path(re.search(r"^opened (.+)$", first, re.M).group(1)))
    assert "Run('uncertain-ridge'" in first and run.name == "uncertain-ridge"
    # What it printed is what the run holds.
    assert f"utc dtype: {run.plan['utc'].dtype}" in plan and "UTC]" in plan
    assert f"over {len(run.plan)} waypoints" in plan
    assert f"lowest battery at a waypoint, Wh: {run.plan['battery_wh'].min()}" in plan
    layer = run.layer("dem")
    assert f"dem: {{'y': {layer.sizes['y']}, 'x': {layer.sizes['x']}}} m from {float(layer.min())}" in dem
    assert "CRS: " in dem and "transform: (" in dem, dem
    series = run.shadows
    assert f"shadow series: {series.sizes['time']} instants" in shadows
    lit = float(re.search(r"lit: ([0-9.]+)", shadows).group(1))
    assert lit == round(float(series.mean("time").mean()), 4) and 0.0 < lit < 1.0
    assert np.isfinite(lit)
    # One figure of two panels, drawn inline.
    images = [o for o in code[4].outputs if "image/png" in o.get("data", {})]
    assert len(images) == 1
