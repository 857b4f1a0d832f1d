//! What the `trundle match` tests share (`match_cmd`, `match_friction`, `match_bowed`):
//! rendering a target or a preset to a mono file, cutting a stretch out of it, and running
//! `trundle match` with its JSON report. Each test binary uses a part of it.
#![allow(dead_code)]

use std::path::Path;
use trundle_test_support::cli::{ok, run, stderr, stdout};

/// `trundle render` in `dir` to the mono file `out`: `args` (e.g. `--preset`, `--seed`,
/// `--seconds`) and each of `sets` as `--set`.
pub fn render(dir: &Path, args: &[&str], sets: &[&str], out: &str) {
    let mut all = vec!["render", "--channels", "1", "-o", out];
    all.extend_from_slice(args);
    for s in sets {
        all.push("--set");
        all.push(s);
    }
    ok(dir, &all);
}

/// [`render`] as 32-bit float, then keep `[from_s, from_s + seconds)` of it (a recording of
/// a rub is taken in its middle, where it has settled).
pub fn render_stretch(
    dir: &Path,
    args: &[&str],
    sets: &[&str],
    out: &str,
    from_s: f64,
    seconds: f64,
) {
    let mut all = vec!["--format", "f32"];
    all.extend_from_slice(args);
    render(dir, &all, sets, out);
    crop(&dir.join(out), from_s, seconds);
}

/// Keep `[from_s, from_s + seconds)` of the mono float WAV `path` (in place).
pub fn crop(path: &Path, from_s: f64, seconds: f64) {
    let mut r = hound::WavReader::open(path).unwrap();
    let spec = r.spec();
    let fs = f64::from(spec.sample_rate);
    let x: Vec<f32> = r.samples::<f32>().map(|s| s.unwrap()).collect();
    let a = (from_s * fs) as usize;
    let b = (a + (seconds * fs) as usize).min(x.len());
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    for &v in &x[a..b] {
        w.write_sample(v).unwrap();
    }
    w.finalize().unwrap();
}

/// `trundle match RECORDING -o m.json --json --jobs 0` in `dir` with `extra` arguments: the
/// JSON report and the exit code.
pub fn matched_file(dir: &Path, recording: &str, extra: &[&str]) -> (serde_json::Value, i32) {
    let mut args = vec!["match", recording, "-o", "m.json", "--json", "--jobs", "0"];
    args.extend_from_slice(extra);
    let o = run(dir, &args);
    let code = o.status.code().unwrap_or(-1);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o))
        .unwrap_or_else(|e| panic!("not JSON ({e}): {} {}", stdout(&o), stderr(&o)));
    (v, code)
}

/// The preset [`matched_file`] wrote (`m.json` in `dir`), as JSON.
pub fn written_preset(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("m.json")).unwrap()).unwrap()
}

/// [`matched_file`] of `target.wav`.
pub fn matched(dir: &Path, extra: &[&str]) -> (serde_json::Value, i32) {
    matched_file(dir, "target.wav", extra)
}
