//! Sun-direction throughput: the planners ask for the Sun at every time step of every
//! LOS map, so this is the ephemeris' hot path (target ≥ 5 M evaluations/s on one core
//! on Mars, ≥ 2 M on the Moon).

use std::hint::black_box;

use areo_ephemeris::{Body, Mars24, Site, SolarGeometry, SunModel, moon, parse_utc};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn sun_direction(c: &mut Criterion) {
    let mut g = c.benchmark_group("sun");
    g.throughput(Throughput::Elements(1));
    let t0 = parse_utc("2012-08-06T05:17:57Z").unwrap();
    let dt0 = areo_ephemeris::MarsTime::from_epoch(t0).days_since_j2000_tt;
    let site = Site::new(-4.5895, 137.4417).unwrap();
    let mut k = 0u32;
    g.bench_function("direction_body_fixed(days_since_j2000)", |b| {
        b.iter(|| {
            k = k.wrapping_add(1);
            black_box(SolarGeometry::sun_state_at_days(black_box(dt0 + f64::from(k % 1000) * 1e-3)))
        })
    });
    g.bench_function("full_geometry(days_since_j2000)", |b| {
        b.iter(|| black_box(SolarGeometry::at_days_since_j2000(black_box(dt0))))
    });
    g.bench_function("Mars24::sun(Epoch)", |b| b.iter(|| black_box(Mars24.sun(black_box(t0)))));
    g.bench_function("azimuth_elevation_at_site", |b| {
        b.iter(|| black_box(SolarGeometry::at_days_since_j2000(black_box(dt0)).state().at_site(&site)))
    });
    // The Moon and the Earth: the Sun's (and on the Moon the Earth's) direction from an
    // Epoch, at a south-polar site (target ≥ 2 M evaluations/s on one core).
    let moon_site = Site::on(Body::Moon, -89.5, 0.0).unwrap();
    g.bench_function("Moon::sun(Epoch)", |b| b.iter(|| black_box(Body::Moon.sun(black_box(t0)))));
    g.bench_function("moon::sky(Epoch) (Sun and Earth)", |b| b.iter(|| black_box(moon::sky(black_box(t0)))));
    g.bench_function("moon_sun_and_earth_at_site", |b| {
        b.iter(|| {
            let s = moon::sky(black_box(t0));
            black_box((s.sun.at_site(&moon_site), s.earth.at_site(&moon_site)))
        })
    });
    // The same sky tabulated as Chebyshev series (a month from t0).
    let table = moon::SkyTable::new(t0, t0 + hifitime::Duration::from_days(30.0));
    g.bench_function("moon::SkyTable::sky(Epoch) (Sun and Earth)", |b| {
        b.iter(|| black_box(table.sky(black_box(t0 + hifitime::Duration::from_seconds(f64::from(k % 1000))))))
    });
    let devon = Site::on(Body::Earth, 75.43, -89.87).unwrap();
    g.bench_function("Earth::sun(Epoch)", |b| b.iter(|| black_box(Body::Earth.sun(black_box(t0)))));
    g.bench_function("earth_sun_at_site", |b| b.iter(|| black_box(Body::Earth.sun(black_box(t0)).at_site(&devon))));
    g.finish();
}

criterion_group!(benches, sun_direction);
criterion_main!(benches);
