//! `trundle tradeoff` in CI: a short scene (1 s) runs, its JSON has a row per setting with
//! the cost and both distances, and the reference row is at distance 0. (One second is far
//! too short for meaningful distances between physics settings — the series' long
//! correlation leaves few independent values; docs/guide/performance.md's table uses 10 s.)

use std::path::Path;
use std::process::Command;

use trundle_test_support::cli::bin;

#[test]
fn tradeoff_json_has_cost_and_both_distances_for_every_row() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("trundle-tradeoff-test");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("t.png");
    let o = Command::new(bin())
        .args(["tradeoff", "--seconds", "1", "--json", "--plot"])
        .arg(&png)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rows = rows.as_array().expect("an array of rows");
    assert!(rows.len() >= 8, "{} rows", rows.len());
    let mut engines = std::collections::BTreeSet::new();
    for r in rows {
        let setting = r["setting"].as_str().expect("setting");
        for key in [
            "ns_per_sample",
            "realtime_factor",
            "series_distance",
            "spectral_distance",
        ] {
            let v = r[key]
                .as_f64()
                .unwrap_or_else(|| panic!("{setting}: no {key}"));
            assert!(v.is_finite() && v >= 0.0, "{setting}: {key} = {v}");
        }
        assert!(
            r["series_distance"].as_f64().unwrap() <= 1.0,
            "KS is at most 1"
        );
        assert!(r["ns_per_sample"].as_f64().unwrap() > 0.0);
        engines.insert(r["engine"].as_str().unwrap().to_string());
        if r["reference"] == true {
            assert_eq!(r["series_distance"].as_f64(), Some(0.0), "{setting}");
            assert_eq!(r["spectral_distance"].as_f64(), Some(0.0), "{setting}");
        }
    }
    assert_eq!(engines.len(), 2, "both engines measured: {engines:?}");
    assert!(rows.iter().any(|r| r["reference"] == true));
    // The plot is a PNG.
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
}

#[test]
fn tradeoff_refuses_a_scene_too_short_for_statistics() {
    let o = Command::new(bin())
        .args(["tradeoff", "--seconds", "0.01"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).starts_with("error: --seconds"));
}
