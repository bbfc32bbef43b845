"""The Python package against the references the Rust tests use and against the
`areo` binary's own outputs (AREO_BIN, default target/debug/areo)."""

import csv
import json
import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import areo

ROOT = Path(__file__).resolve().parents[2]
GALE = ROOT / "crates/terrain/tests/data/gale_mola_crop_64.tif"
RIDGE = ROOT / "scenarios/uncertain-ridge.ron"
LSR1 = ROOT / "crates/rover/params/lsr1.ron"


def areo_bin():
    path = Path(os.environ.get("AREO_BIN", ROOT / "target/debug/areo"))
    if not path.exists():
        pytest.fail(f"the areo binary is not at {path}: build it (cargo build) or set AREO_BIN")
    return str(path)


def cli(*args):
    subprocess.run([areo_bin(), "-q", *map(str, args)], check=True)


# The GISS Mars24 worked examples (Allison & McEwen 2000, 2018 constants), as
# crates/ephemeris/tests/worked_examples.rs checks them.
def test_sun_matches_the_mars24_worked_example_a():
    s = areo.sun("2000-01-06T00:00:00Z", 0.0, 0.0)
    assert s["distance_au"] == pytest.approx(1.393584, abs=1e-6)  # D-2
    assert s["subsolar_lon_east_deg"] == pytest.approx(185.274004, abs=1e-5)  # C-5
    assert s["local_solar_time_h"] == pytest.approx(23.64840, abs=1e-5)  # C-4
    # D-5, D-6 are the page's spherical formulas; areo's geometric ones on the
    # ellipsoid differ by up to a quarter degree.
    assert s["azimuth_deg"] == pytest.approx(191.039051, abs=0.3)
    assert s["elevation_deg"] == pytest.approx(90.0 - 154.261757, abs=0.3)
    assert s["utc"] == "2000-01-06T00:00:00.000Z"


def test_sun_matches_the_mars24_worked_example_b_at_spirits_site():
    s = areo.sun("2004-01-03T13:46:31Z", -14.640, 360.0 - 184.702)
    assert s["distance_au"] == pytest.approx(1.477672, abs=1e-6)  # D-2
    assert 360.0 - s["subsolar_lon_east_deg"] == pytest.approx(4.705, abs=1e-3)  # C-5
    # Local true midnight (C-4: 0.00020 h).
    lt = s["local_solar_time_h"]
    assert min(lt, 24.0 - lt) == pytest.approx(0.0002, abs=1e-5)


def test_sun_series_equals_the_sun_at_each_instant():
    t0 = 947116800.0  # 2000-01-06T00:00:00Z
    times = t0 + np.arange(0.0, 88775.0, 3600.0)
    series = areo.sun_series(times, -4.6, 137.4)
    assert set(series) == {"azimuth_deg", "elevation_deg", "distance_au", "subsolar_lat_deg",
                           "subsolar_lon_east_deg", "local_solar_time_h"}
    for k, t in enumerate(times):
        one = areo.sun(float(t), -4.6, 137.4)
        for key, values in series.items():
            assert values.dtype == np.float64 and values[k] == one[key]
    # A sol at Gale: the Sun rises and sets once.
    up = series["elevation_deg"] > 0
    assert 0 < up.sum() < len(times)


def test_the_moon_and_the_earth_have_suns_too_and_a_bad_body_is_refused():
    moon = areo.sun("2024-06-01T00:00:00Z", -89.5, 0.0, body="moon")
    assert abs(moon["elevation_deg"]) < 2.0  # a polar Sun skims the horizon
    earth = areo.sun("2024-06-21T12:00:00Z", 0.0, 0.0, body="earth")
    assert earth["elevation_deg"] > 60.0
    with pytest.raises(ValueError, match="mars, moon, earth"):
        areo.sun("2024-06-21T12:00:00Z", 0.0, 0.0, body="pluto")
    with pytest.raises(ValueError):
        areo.sun("not a time", 0.0, 0.0)


def test_read_dem_gives_heights_cell_size_and_crs():
    dem = areo.read_dem(GALE)
    z = dem.heights
    assert z.shape == (dem.rows, dem.cols) == (64, 64) and z.dtype == np.float32
    # One array, read-only, handed out at every access.
    assert dem.heights is z and not z.flags.writeable
    with pytest.raises(ValueError):
        z[0, 0] = 0.0
    dx, dy = dem.cell_size
    assert dx > 0 and dy > 0
    gt = dem.geotransform
    assert gt[1] == dx and gt[5] == -dy
    assert "Equidistant Cylindrical" in dem.crs and "Mars" in dem.crs
    # The binary reads the same grid (its info report: cell size, elevation range).
    info = subprocess.run([areo_bin(), "terrain", "info", str(GALE)], check=True, capture_output=True,
                          text=True).stdout
    fields = dict(line.strip().split(None, 1) if " " in line.strip() else (line.strip(), "")
                  for line in info.splitlines()[1:] if line.strip())
    cell = fields["cell"].split()  # "size 461.0008… m x 463.0576… m"
    assert (dx, dy) == (float(cell[1]), float(cell[4]))
    lo, hi = fields["elevation"].split()[0], fields["elevation"].split()[2]
    assert (float(np.nanmin(z)), float(np.nanmax(z))) == (float(lo), float(hi))
    # The MOLA sphere the file declares, named as every file of a run names it.
    assert 'ELLIPSOID["Mars - Sphere, R = 3396000 m",3396000,0,' in dem.crs


def test_shadow_equals_the_binarys_map_bit_for_bit(tmp_path):
    dem = areo.read_dem(GALE)
    for az, el, curved in [(90.0, 5.0, True), (217.0, 12.5, True), (300.0, 3.0, False)]:
        ours = areo.shadow(dem, az, el, curved=curved)
        assert ours.dtype == np.uint8 and ours.shape == (64, 64)
        out = tmp_path / f"shadow_{az}.tif"
        cli("terrain", "shadow", GALE, "--sun-azimuth", az, "--sun-elevation", el, "-o", out,
            *([] if curved else ["--flat"]))
        theirs = areo.read_dem(out).heights  # uint8 read as heights; 255 (no data) as NaN
        expect = np.where(np.isnan(theirs), 255, theirs).astype(np.uint8)
        assert np.array_equal(ours, expect), (az, el)
        assert 0 < (ours == 0).sum() < ours.size  # some shadow, not all
    with pytest.raises(ValueError):
        areo.shadow(dem, 90.0, 95.0)


def test_sun_over_a_polar_map_is_turned_onto_its_grid(tmp_path):
    # A south polar grid with central meridian 0 whose middle is at 90°E: near the pole
    # the Sun lies toward the subsolar meridian, so its grid azimuth is the subsolar
    # longitude; the shadow at that azimuth is the binary's `--utc` map bit for bit.
    polar_path = ROOT / "crates/terrain/tests/data/polar_lon0_64.tif"
    polar = areo.read_dem(polar_path)
    t = "2025-01-01T00:00:00Z"
    sun = polar.sun_over(t)
    assert sun["body"] == "Moon" and abs(sun["lon_east_deg"] - 90.0) < 1e-6
    subsolar = areo.sun(t, sun["lat_deg"], sun["lon_east_deg"], body="moon")["subsolar_lon_east_deg"]
    assert abs(sun["grid_azimuth_deg"] - subsolar) < 0.1
    assert abs(sun["grid_azimuth_deg"] - sun["azimuth_deg"] - 90.0) < 1e-6
    out = tmp_path / "polar.tif"
    cli("terrain", "shadow", polar_path, "--utc", t, "-o", out)
    theirs = areo.read_dem(out).heights
    ours = areo.shadow(polar, sun["grid_azimuth_deg"], sun["elevation_deg"])
    assert np.array_equal(ours, np.where(np.isnan(theirs), 255, theirs).astype(np.uint8))
    # On Gale's equirectangular crop the grid's north is true north.
    gale = areo.read_dem(GALE).sun_over("2012-08-06T22:00:00Z")
    assert gale["grid_azimuth_deg"] == gale["azimuth_deg"]
    with pytest.raises(areo.AreoError):
        areo.read_dem(GALE).sun_over("not a time")


def test_horizon_equals_the_binarys_maps(tmp_path):
    dem = areo.read_dem(GALE)
    h = areo.horizon(dem, 16)
    assert h.shape == (16, 64, 64) and h.dtype == np.float32
    stem = tmp_path / "h"
    cli("terrain", "horizon", GALE, "--sectors", 16, "-o", stem)
    for s in range(16):
        theirs = areo.read_dem(stem / f"s{s:03d}.tif").heights
        assert np.array_equal(h[s], theirs), s
    # The horizon decides the cast shadow: where the Sun stands a degree above it a
    # cell is not in cast shadow (self-shadow aside), a degree below it always is.
    sun = areo.shadow(dem, 0.0, 10.0)
    assert np.all(sun[h[0] > 11.0] == 0)


def test_a_runs_report_is_the_binarys_with_tables_as_columns_and_rasters_as_arrays(tmp_path):
    shadows = ROOT / "scenarios/crater-morning-shadows.ron"
    result = areo.Scenario.load(shadows).run(out=tmp_path / "py")
    report = result.report
    out = subprocess.run([areo_bin(), "-q", "run", str(shadows), "--out", str(tmp_path / "cli"), "--json"],
                         check=True, capture_output=True, text=True)
    cli_report = json.loads(out.stdout)["report"]
    assert report["job"] == cli_report["job"] == "TerrainShadow"
    for name in ("lit_fraction", "cast_shadow_fraction", "relief_m", "cells"):
        assert report[name] == cli_report[name]
    assert report["sun"]["elevation_deg"] == result.facts["sun.elevation_deg"]
    rows, cols = report["grid"]["rows"], report["grid"]["cols"]
    sun = report["direct_sun"]
    assert sun.shape == (rows, cols) and report["preview_rgb"].shape == (rows, cols, 3)
    # The raster is the lit fraction's source: cells with data (not 255) in direct sun (1).
    valid = sun != 255
    assert (sun[valid] == 1).mean() == pytest.approx(report["lit_fraction"], abs=1e-12)
    assert np.isnan(report["elevation_m"][~valid]).all()
    assert np.nanmax(report["elevation_m"]) - np.nanmin(report["elevation_m"]) == pytest.approx(report["relief_m"], rel=1e-6)

    table = areo.Scenario.load(ROOT / "scenarios/gale-sol-sun.ron").run(out=tmp_path / "sun").report["table"]
    assert isinstance(table["elevation_deg"], np.ndarray) and len(table["elevation_deg"]) == 148
    # A row is sunlit where the Sun stands above the horizon mask.
    assert table["sunlit"].dtype == bool
    assert (table["sunlit"] == (table["elevation_deg"] > table["horizon_deg"])).all()


def test_a_scenario_run_gives_the_binarys_facts_and_tables(tmp_path):
    result = areo.Scenario.load(RIDGE).run(out=tmp_path / "py")
    cli("run", RIDGE, "-o", tmp_path / "cli")
    with open(tmp_path / "cli" / "uncertain-ridge" / "facts.json") as f:
        facts = json.load(f)
    ours = result.facts
    timing = {k for k in facts if k.endswith("_s") and ("plan" in k or "precalc" in k) or "memory" in k}
    assert set(ours) == set(facts)
    for k in set(facts) - timing:
        assert ours[k] == facts[k], k
    plan = result.table("plan")
    assert len(plan["t_s"]) == ours["initial_plan_waypoints"]
    assert plan["action"][0] in {"hibernate", "drive", "charge", "start", "wait"}
    assert "monte_carlo" in result.tables and len(result.tables["monte_carlo"]["run"]) == 2000
    # The same table as a NumPy record array: numbers as float64, text as text.
    arr = result.table_array("plan")
    assert len(arr) == len(plan["t_s"]) and arr["t_s"].dtype == np.float64 and arr["action"].dtype.kind == "U"
    assert np.array_equal(arr["t_s"], plan["t_s"]) and list(arr["action"]) == list(plan["action"])
    # The tables come from the report, not the CSVs: plan.csv holds the same rows at
    # its columns' decimals.
    with open(result.out / "plan.csv") as f:
        written = list(csv.DictReader(f))
    assert [r["action"] for r in written] == list(arr["action"])
    assert np.allclose([float(r["t_s"]) for r in written], arr["t_s"], atol=0.05)
    assert np.allclose([float(r["battery_wh"]) for r in written], arr["battery_wh"], atol=0.005)
    assert any(p.name == "facts.json" for p in result.files)
    # The report holds the figures the facts name and the plan itself, its waypoints as
    # columns: the plan table's rows are the report's waypoints.
    report = result.report
    assert report["job"] == "Tempest" and report["initial_plan_waypoints"] == ours["initial_plan_waypoints"]
    assert report["mc"]["success_probability"] == ours["mc.success_probability"]
    waypoints = report["plan"]["waypoints"]
    assert np.allclose(waypoints["t_s"], arr["t_s"], atol=0.05)
    assert report["plan"]["e_max_wh"] == ours["e_max_wh"]
    # The plan table is in the report too, its columns at full precision.
    table = report["tables"]["plan"]
    assert np.array_equal(table["sol"], arr["sol"]) and list(table["action"]) == list(arr["action"])
    assert np.allclose(table["lat_deg"], arr["lat_deg"], atol=5e-8)
    # The plots are in the report as plain data, a file of each name written; without
    # a simulation the energy plot's first series is the plan's required energy, the
    # plan table's column.
    names = list(report["plots"]["name"])
    assert {"route", "distance", "energy", "mc_arrival"} <= set(names)
    assert all((result.out / f"{n}.svg").exists() for n in names)
    energy = report["plots"]["drawing"][names.index("energy")]
    assert energy["kind"] == "time"
    required = np.array(energy["series"]["points"][0])[:, 1]
    assert np.allclose(required, table["required_wh"])


def routes_are_strict_geojson_and_mmgis(out, name):
    """The checks of a run's routes in `out` (run `name`): geojson-pydantic validates
    RFC 7946's structure (no empty box, positions of two or three numbers; installed in
    the test environment by .ci/run), MMGIS's rules for the enhanced route in time, and
    the MMGIS layer beside it."""
    from geojson_pydantic import Feature, FeatureCollection

    with open(out / "route.geojson") as f:
        route = json.load(f)
    FeatureCollection.model_validate(route)
    with open(out / "route_time.geojson") as f:
        timed = json.load(f)
    # MMGIS's enhanced GeoJSON: the route's vertices carry more values than a position,
    # named by coord_properties, whose first three MMGIS reads by name.
    line, *actions = timed["features"]
    names = line["properties"]["coord_properties"]
    assert names[:3] == ["longitude", "latitude", "elevation"]
    vertices = line["geometry"]["coordinates"]
    assert line["geometry"]["type"] == "LineString" and len(vertices) >= 2
    assert all(len(v) == len(names) for v in vertices)
    assert all(-180 <= v[0] <= 180 and -90 <= v[1] <= 90 for v in vertices)
    # The rest of the file is plain GeoJSON: a box, if any, of two numbers per dimension,
    # and one feature per action with the instants a time slider filters on.
    assert "bbox" not in timed or len(timed["bbox"]) in (4, 6)
    rest = FeatureCollection.model_validate({**timed, "features": actions})
    assert len(rest.features) == len(vertices) - 1
    for a in actions:
        Feature.model_validate(a)
        assert a["properties"]["start_utc"] <= a["properties"]["end_utc"]
    # The MMGIS layer beside it names what the file holds: the time properties every
    # feature has, and vertex values to colour the route by.
    with open(out / "route_time.mmgis.json") as f:
        layer = json.load(f)
    assert layer["type"] == "vector" and (out / layer["url"]).exists()
    # Named after the run (not the directory the files were staged in).
    assert layer["name"] == f"{name}: route in time"
    time = layer["time"]
    assert time["enabled"] is True and time["type"] == "local"
    assert all(time["startProp"] in x["properties"] and time["endProp"] in x["properties"] for x in timed["features"])
    gradient = layer["variables"]["pathAttachments"]["gradient"]
    assert gradient["colorWithProp"] == "battery_wh"
    assert {gradient["colorWithProp"], *gradient["dropdownColorWithProp"]} <= set(names)
    assert len(gradient["colorRamp"]) >= 2
    return route


def test_the_routes_pass_a_strict_geojson_validator_and_mmgis_rules_and_come_with_a_layer(tmp_path):
    cli("run", RIDGE, "-o", tmp_path)
    route = routes_are_strict_geojson_and_mmgis(tmp_path / "uncertain-ridge", "uncertain-ridge")
    assert route["body"]["name"] == "Mars"


# A plan of about 1.5 km across a small synthesised map at any site on any body (as
# tests/gis.rs and tests/cesium.rs run it).
SMALL_ROUTE = (ROOT / "tests/tempest/small-route.ron.in").read_text()


def small_route(body, lat, lon, utc):
    """The small route's scenario text on `body` at (`lat`, `lon`), starting at `utc`."""
    text = SMALL_ROUTE
    for token, value in (("@BODY@", body), ("@LAT@", repr(float(lat))), ("@LON@", repr(float(lon))), ("@UTC@", utc)):
        text = text.replace(token, value)
    return text


@pytest.mark.parametrize("body,lat,lon,utc", [
    ("Moon", -20.0, 10.0, "2025-01-10T00:00:00Z"),
    ("Earth", 75.43, -89.87, "2025-06-21T12:00:00Z"),
])
def test_the_moon_and_earth_routes_pass_the_same_checks_on_their_bodies(tmp_path, body, lat, lon, utc):
    name = body.lower()
    scenario = tmp_path / f"{name}.ron"
    scenario.write_text(small_route(body, lat, lon, utc))
    cli("run", scenario, "-o", tmp_path)
    route = routes_are_strict_geojson_and_mmgis(tmp_path / name, name)
    assert route["body"]["name"] == body
    # Longitudes east, -180..180, near the site's (the Earth's west of Greenwich).
    points = route["features"][0]["geometry"]["coordinates"]
    assert all(abs(p[0] - lon) < 0.5 and abs(p[1] - lat) < 0.5 for p in points), points[:3]


def test_set_changes_a_field_and_refuses_a_bad_one():
    sc = areo.Scenario.load(RIDGE)
    assert sc.set("job.uncertainty.terrain_plan_clones", 0) is sc
    assert sc.sets == ["job.uncertainty.terrain_plan_clones=0"]
    with pytest.raises(areo.ScenarioError) as e:
        sc.set("job.tau", -1.0)
    err = e.value
    assert err.field == "job.tau" and err.file.endswith("uncertain-ridge.ron")
    assert err.line > 0 and err.column > 0
    assert sc.sets == ["job.uncertainty.terrain_plan_clones=0"]  # the bad value not kept
    with pytest.raises(areo.ScenarioError):
        sc.set("job.no_such_field", 1)


def test_an_unreachable_goal_raises_unreachable_with_its_binding(tmp_path):
    sc = areo.Scenario.load(RIDGE).set("job.start_battery_above_floor_wh", 1)
    with pytest.raises(areo.Unreachable) as e:
        sc.run(out=tmp_path)
    assert e.value.binding == "Battery"
    assert isinstance(e.value.result, areo.RunResult) and "initial_plan_waypoints" not in e.value.result.facts
    # The scenario plans exactly on a 60 s tick: the verdict is a proof at that tick,
    # and the message says what it proves.
    assert e.value.result.facts["unreachable_proven"] is True
    assert "proven at the tick of 60 s" in e.value.message and "not a proof" not in e.value.message


def test_a_run_keeps_to_its_work_budget(tmp_path):
    # devon-island on the approximate planner's former classes: from an empty battery
    # that search floods the map (on its shipped tick the exact search plans at once).
    text = (ROOT / "scenarios" / "devon-island.ron").read_text()
    assert "tick_s: 300," in text
    text = text.replace("tick_s: 300,", "approximate: true, resolution: (time_s: 1800, energy_wh: 50), goal_times: 12, segment_starts: 8,")
    text = text.replace('"rovers/', '"' + str(ROOT / "scenarios" / "rovers") + "/")
    devon = tmp_path / "devon-island.ron"
    devon.write_text(text)
    sc = areo.Scenario.load(devon).set("job.start_battery_above_floor_wh", 0.001)
    # Admitted (its certain work is the 640 000 horizon rays), then stopped where
    # the budget ends: the budget less the sweeps, 100 steps an expansion, as
    # `areo run --max-work 2.4064e8` does.
    with pytest.raises(areo.AreoError) as e:
        sc.run(out=tmp_path, max_work=2.4064e8)
    assert not isinstance(e.value, areo.Unreachable)
    assert isinstance(e.value, areo.BudgetSpent)
    assert e.value.result.facts["status"] == "stopped"
    assert e.value.result.facts["stopped_by"] == "work"
    assert e.value.result.facts["no_plan_expansions"] > 100000
    assert e.value.file.endswith("devon-island.ron")
    assert "stopped after the work of 2400000 label expansions" in str(e.value)
    with pytest.raises(ValueError):
        sc.run(out=tmp_path, max_work=0)


def test_bad_files_raise_with_the_file_named(tmp_path):
    with pytest.raises(areo.AreoError) as e:
        areo.read_dem(tmp_path / "missing.tif")
    assert e.value.file.endswith("missing.tif")
    bad = tmp_path / "bad.ron"
    bad.write_text("Scenario(version: 1, job: Tempest(tau: )")
    with pytest.raises(areo.ScenarioError) as e:
        areo.Scenario.load(bad)
    assert e.value.file.endswith("bad.ron") and e.value.line == 1


def test_rover_check_equals_the_binarys_report():
    ours = areo.rover_check(LSR1, terrain="slope:20", mu=0.6)
    out = subprocess.run([areo_bin(), "rover", "check", str(LSR1), "--terrain", "slope:20", "--mu", "0.6",
                          "--format", "json"], check=True, capture_output=True, text=True).stdout
    assert ours == json.loads(out)
    assert ours["verdict"] == "ok" and math.isclose(ours["pose"]["pitch_deg"], 20.0, abs_tol=1e-6)
    with pytest.raises(ValueError, match="terrain"):
        areo.rover_check(LSR1, terrain="cliff:3")


def test_rover_check_of_a_resource_model_equals_the_binarys_report():
    model = ROOT / "scenarios/rovers/lunar-polar-rover.ron"
    ours = areo.rover_check(model, terrain="slope:10", body="moon")
    out = subprocess.run([areo_bin(), "rover", "check", str(model), "--terrain", "slope:10", "--body", "moon",
                          "--format", "json"], check=True, capture_output=True, text=True).stdout
    assert ours == json.loads(out)
    # The file gives no gravity: the Moon's, and the usable battery is its SoC window.
    assert ours["gravity_from"] == "Moon" and math.isclose(ours["gravity_m_s2"], 1.622)
    assert [d["ground"] for d in ours["drives"]] == ["flat", "up 10°", "down 10°", "up 15° (maximum)"]
    with pytest.raises(ValueError, match="body"):
        areo.rover_check(model, body="venus")


def test_ctrl_c_interrupts_a_long_run(tmp_path):
    # lunar-south-pole-10m plans four days on 10 m cells: about a minute. Interrupted
    # after 3 s, Python must raise KeyboardInterrupt at once.
    import signal
    import sys
    import time

    script = (
        "import areo, sys\n"
        f"areo.Scenario.load({str(ROOT / 'scenarios/lunar-south-pole-10m.ron')!r}).run(out={str(tmp_path)!r})\n"
        "print('finished')\n"
    )
    started = time.monotonic()
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(3.0)
    assert proc.poll() is None, "the run ended before it could be interrupted"
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=30)
    assert "KeyboardInterrupt" in err and "finished" not in out, err
    assert time.monotonic() - started < 15.0
