"""`areo.open`: a run the `areo` binary wrote (AREO_BIN), read back as pandas and
xarray, against the files themselves read another way (the csv module, `read_dem`,
`shadows/index.json`), and by rioxarray/pyproj for its georeference."""

import csv
import json
import math

from pathlib import Path

import numpy as np
import pytest
from pystac.validation.stac_validator import JsonSchemaSTACValidator

import areo
from areo.plot import hillshade
from areo.run import cell_centres
from test_areo import RIDGE, ROOT, cli, small_route


@pytest.fixture(scope="module")
def ridge(tmp_path_factory):
    out = tmp_path_factory.mktemp("open")
    cli("run", RIDGE, "-o", out)
    return out


def test_a_runs_tables_are_dataframes_with_utc_times(ridge):
    run = areo.open(ridge)
    # The output directory holding one run opens that run, as its own directory does.
    assert run.path == areo.open(ridge / "uncertain-ridge").path == ridge / "uncertain-ridge"
    assert set(run.table_names) == {"plan", "monte_carlo"} and {"dem", "slope", "direct_sun"} <= set(run.layer_names)
    plan = run.plan
    with open(run.path / "plan.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(plan) == len(rows) == run.facts["initial_plan_waypoints"]
    assert plan["utc"].dtype.kind == "M" and str(plan["utc"].dt.tz) == "UTC" and plan["end_utc"].dtype.kind == "M"
    # The times agree with the seconds beside them (written to a tenth): each waypoint
    # lasts its duration and starts t_s after the first.
    lasts = (plan["end_utc"] - plan["utc"]).dt.total_seconds().to_numpy()
    assert np.allclose(lasts, plan["duration_s"], atol=0.05) and lasts.sum() > 3600
    since = (plan["utc"] - plan["utc"].iloc[0]).dt.total_seconds().to_numpy()
    assert np.allclose(since, plan["t_s"] - plan["t_s"].iloc[0], atol=0.05)
    assert plan["utc"].iloc[0].isoformat().startswith(rows[0]["utc"][:19])
    assert np.array_equal(plan["battery_wh"].to_numpy(), [float(r["battery_wh"]) for r in rows])
    assert list(plan["action"]) == [r["action"] for r in rows]
    assert plan["goal"].notna().sum() == sum(1 for r in rows if r["goal"])
    mc = run.table("monte_carlo")
    assert len(mc) == 2000
    with pytest.raises(KeyError, match="replans.*its tables: monte_carlo, plan"):
        run.table("replans")


def test_a_runs_maps_are_dataarrays_on_the_maps_grid_and_body(ridge):
    run = areo.open(ridge)
    dem = run.layer("dem")
    read = areo.read_dem(run.path / "dem.tif")
    assert dem.dims == ("y", "x") and dem.shape == read.heights.shape
    assert np.array_equal(dem.values, read.heights.astype(np.float64), equal_nan=True)
    x0, dx, _, y_top, _, minus_dy = read.geotransform
    assert np.allclose(dem["x"], x0 + dx * (np.arange(read.cols) + 0.5))
    assert np.allclose(dem["y"], y_top + minus_dy * (np.arange(read.rows) + 0.5))
    assert dem.attrs["units"] == "m" and run.layer("slope").attrs["units"] == "degree"
    # The route's cells lie on the map: each waypoint's cell centre in map metres is
    # where its scenario metres put it, from the map's south-west corner.
    plan = run.plan
    px, py = cell_centres(dem, plan["col"], plan["row"])
    assert np.allclose(px - (x0), plan["x_m"], atol=0.01)
    assert np.allclose(py - (y_top + minus_dy * read.rows), plan["y_m"], atol=0.01)
    with pytest.raises(KeyError, match="classes"):
        run.layer("classes")


def test_rioxarray_reads_the_maps_crs_on_mars_and_its_transform(ridge):
    import rioxarray  # noqa: F401 - the .rio accessor (installed in CI's environment)
    from pyproj import CRS

    run = areo.open(ridge)
    dem = run.layer("dem")
    crs = dem.rio.crs
    assert crs is not None
    # Mars's sphere, as dem.tif and the CZML name it (pyproj reads the WKT).
    ellipsoid = CRS.from_wkt(crs.to_wkt()).ellipsoid
    assert ellipsoid.semi_major_metre == 3_396_000 and ellipsoid.semi_minor_metre == 3_396_000
    gt = areo.read_dem(run.path / "dem.tif").geotransform
    assert tuple(dem.rio.transform())[:6] == pytest.approx(tuple(gt[i] for i in (1, 2, 0, 4, 5, 3)))


def test_the_shadow_series_is_one_time_indexed_dataarray(ridge):
    run = areo.open(ridge)
    series = run.shadows
    with open(run.path / "shadows" / "index.json") as f:
        index = json.load(f)
    assert series.dims == ("time", "y", "x") and series.sizes["time"] == len(index)
    unix = series["time"].values.astype("datetime64[ms]").astype(np.int64) / 1000.0
    assert np.array_equal(unix, [e["unix_s"] for e in index])
    for k in (0, len(index) // 2, len(index) - 1):
        frame = areo.read_layer(str(run.path / "shadows" / index[k]["file"]))["values"]
        assert np.array_equal(series.isel(time=k).values, frame.astype(np.float32), equal_nan=True)
    values = series.values[~np.isnan(series.values)]
    assert set(np.unique(values)) <= {0.0, 1.0} and 0.0 < values.mean() < 1.0
    # direct_sun.tif is the series' frame at its own instant.
    at = run.facts["layers.direct_sun_utc"]
    k = [e["utc"] for e in index].index(at)
    assert np.array_equal(series.isel(time=k).values, run.layer("direct_sun").values.astype(np.float32), equal_nan=True)


def test_a_class_maps_codes_carry_their_names(tmp_path):
    cli("run", ROOT / "scenarios/gale-ground.ron", "-o", tmp_path)
    run = areo.open(tmp_path)
    classes = run.layer("classes")
    assert classes.attrs["categories"] == {1: "smooth", 2: "rough", 3: "blocky"}
    assert list(classes.attrs["flag_values"]) == [1, 2, 3] and classes.attrs["flag_meanings"] == "smooth rough blocky"
    # The codes are the cells' classes: as many of each as the run's facts count.
    for code, name in classes.attrs["categories"].items():
        assert int((classes.values == code).sum()) == run.facts[f"terrain_classes.classes.{name}.cells"]
    mask = run.layer("no_go")
    assert mask.attrs["categories"][1] == "marked by the mask" and mask.attrs["flag_meanings"].startswith("free marked_by")
    assert int((mask.values == 2).sum()) == 19


def test_opening_what_is_not_a_run_says_what_is_expected(tmp_path):
    with pytest.raises(areo.AreoError, match="not a directory"):
        areo.open(tmp_path / "missing")
    with pytest.raises(areo.AreoError, match=r"expected one run's outputs.*found none"):
        areo.open(tmp_path)


def test_hillshade_of_planes_is_lamberts_law():
    flat = hillshade(np.zeros((5, 6)), 10.0, 10.0, azimuth_deg=90.0, altitude_deg=30.0)
    assert np.allclose(flat, math.sin(math.radians(30.0)))
    # Rising 1 in 1 to the east, lit from the east at 45°: the Sun grazes it. Lit from
    # the west it is square to the beam.
    east = np.tile(np.arange(6) * 10.0, (5, 1))
    assert np.allclose(hillshade(east, 10.0, 10.0, azimuth_deg=90.0, altitude_deg=45.0), 0.0, atol=1e-12)
    assert np.allclose(hillshade(east, 10.0, 10.0, azimuth_deg=270.0, altitude_deg=45.0), 1.0)
    # Rising to the north (rows run south): lit from the north at 45° it grazes.
    north = np.tile((np.arange(5)[::-1] * 10.0)[:, None], (1, 6))
    assert np.allclose(hillshade(north, 10.0, 10.0, azimuth_deg=0.0, altitude_deg=45.0), 0.0, atol=1e-12)


def test_the_plot_helpers_draw_the_plans_route_and_battery(ridge):
    import matplotlib

    matplotlib.use("Agg")
    run = areo.open(ridge)
    ax = run.plot_route()
    line = next(li for li in ax.get_lines() if li.get_label() == "route")
    px, py = cell_centres(run.layer("dem"), run.plan["col"], run.plan["row"])
    assert np.allclose(line.get_xdata(), px) and np.allclose(line.get_ydata(), py)
    goals = next(li for li in ax.get_lines() if li.get_label() == "goal")
    assert len(goals.get_xdata()) == run.plan["goal"].notna().sum() >= 1
    ax = run.plot_battery()
    line = next(li for li in ax.get_lines() if li.get_label() == "battery")
    assert np.array_equal(line.get_ydata(), run.plan["battery_wh"].to_numpy())


class CoreSchemasOnly(JsonSchemaSTACValidator):
    """STAC 1.1's core schemas, which pystac ships: the extensions' schemas (ssys,
    projection) are on the web, and the tests run offline; their fields are checked
    by hand below."""

    def validate_extension(self, *args, **kwargs):
        return None


def stac_holds_the_route(run):
    """The shadow series' STAC collection of `run`, read by pystac: STAC 1.1's core
    schemas accept it, every item is one file at its instant on the run's body, and the
    route lies inside each item's footprint."""
    import pystac
    from pystac.validation import validate_dict

    folder = run.path / "shadows"
    with open(folder / "index.json") as f:
        index = json.load(f)
    with open(folder / "collection.json") as f:
        collection_dict = json.load(f)
    validate_dict(collection_dict, validator=CoreSchemasOnly())
    collection = pystac.Collection.from_file(str(folder / "collection.json"))
    items = sorted(collection.get_items(), key=lambda i: i.datetime)
    assert len(items) == len(index)
    with open(run.path / "route.geojson") as f:
        route = json.load(f)
    body = route["body"]["name"]
    lons, lats = zip(*[c[:2] for c in route["features"][0]["geometry"]["coordinates"]])
    shape = list(run.shadows.shape[1:])
    validator = CoreSchemasOnly()
    for k in (0, len(items) // 2, len(items) - 1):
        with open(folder / f"{items[k].id}.json") as f:
            validate_dict(json.load(f), validator=validator)
    for item, entry in zip(items, index):
        # Each item is one file of the series at its instant, on the run's body.
        assert item.datetime.timestamp() == entry["unix_s"]
        asset = item.assets["data"]
        assert Path(asset.get_absolute_href()).resolve() == (folder / entry["file"]).resolve()
        assert asset.media_type == "image/tiff; application=geotiff; profile=cloud-optimized"
        assert item.properties["ssys:targets"] == [body]
        assert item.properties["proj:shape"] == shape
        # The route lies inside the item's footprint.
        west, south, east, north = item.bbox
        assert west <= min(lons) and max(lons) <= east and south <= min(lats) and max(lats) <= north
    extent = collection.extent.temporal.intervals[0]
    assert (extent[0].timestamp(), extent[1].timestamp()) == (index[0]["unix_s"], index[-1]["unix_s"])
    assert collection.extent.spatial.bboxes[0] == items[0].bbox
    return body


def test_the_shadow_series_is_a_stac_collection_pystac_reads(ridge):
    assert stac_holds_the_route(areo.open(ridge)) == "Mars"


@pytest.mark.parametrize("body,lat,lon,utc", [
    ("Moon", -89.2, 45.0, "2024-03-01T00:00:00Z"),
    ("Earth", 75.43, -89.87, "2025-06-21T12:00:00Z"),
])
def test_the_stac_series_of_a_moon_and_an_earth_run_is_on_its_body(tmp_path, body, lat, lon, utc):
    scenario = tmp_path / f"{body.lower()}.ron"
    scenario.write_text(small_route(body, lat, lon, utc))
    cli("run", scenario, "-o", tmp_path)
    run = areo.open(tmp_path / body.lower())
    assert stac_holds_the_route(run) == body
    # The footprint is the small map's at the site (the Earth's west of Greenwich).
    with open(run.path / "shadows" / "collection.json") as f:
        west, south, east, north = json.load(f)["extent"]["spatial"]["bbox"][0]
    assert lat - 0.5 < south < north < lat + 0.5 and west < lon < east, (west, south, east, north)
