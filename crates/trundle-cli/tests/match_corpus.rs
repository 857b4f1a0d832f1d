//! `trundle match` held to the real texture corpus (issue #25, "What it must show"): every
//! clip of `trundle_test_support::texture_corpus` (tyres, saws, grinding, a dirt track,
//! traffic, bowed strings) is matched with the command as a user runs it (default settings,
//! `--jobs` = the cores), and the preset it writes is then judged the way the held-out check
//! judges one, with nothing the search saw:
//!
//! * rendered by `trundle render --preset` (the body EQ as the preset plays it) at three
//!   seeds the match never heard ([`SEEDS`]), as long as the whole clip, and compared with
//!   the whole clip by `trundle compare`'s four measures: all four at every seed;
//! * closer than noise shaped to the clip's long-term spectrum on modulation and on texture,
//!   at every seed;
//! * rendered with `body_eq=0` (the model's own spectrum): third-octave spectrum within
//!   [`OWN_SPECTRUM_LIMIT_DB`] of the clip (the mean over the seeds);
//! * rendered at 1.5× its velocity: spectral centroid at least [`MIN_BRIGHTNESS`] times the
//!   centroid as matched (the mean over the seeds);
//! * the match's CPU time at most [`CPU_S_PER_5_S`] per 5 s of recording matched.
//!
//! Clips known to miss a bar today are listed in [`KNOWN_OUTSIDE`] with why; every other
//! clip must pass all of them, and when a known one comes inside the test says so. The
//! README's table is printed:
//!
//! ```sh
//! cargo test -p trundle-cli --test match_corpus -- --ignored --nocapture
//! ```
//!
//! For a closer look, `TRUNDLE_MATCH_CLIPS=saw,cello` runs only the clips whose names
//! contain one of the words, `TRUNDLE_MATCH_JOBS=1` sets `--jobs`, `TRUNDLE_MATCH_ARGS`
//! adds arguments to `trundle match` (space-separated), `TRUNDLE_MATCH_BIN` runs another
//! build of the binary, and `TRUNDLE_MATCH_KEEP=DIR` writes every clip, preset and render
//! there; the assertions then apply to the clips run.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;
use trundle_dsp::analysis::compare::{compare, Comparison};
use trundle_test_support::scratch::scratch;
use trundle_test_support::texture_corpus::{load, shaped_noise, Clip, Texture, CORPUS};
use trundle_test_support::wav::{read_wav_mono, write_wav};

/// Seeds the presets are rendered at for the verdicts: neither the match's search seeds
/// (1, 2) nor its own validation seeds (1001, 2002, 3003).
const SEEDS: [u32; 3] = [4004, 5005, 6006];
/// Seed of the shaped noise (the one of `docs/corpus.md`'s calibration).
const NOISE_SEED: u64 = 25;
/// The issue's bar for the model's own spectrum (`body_eq=0`): RMS third-octave difference
/// (dB) from the clip.
const OWN_SPECTRUM_LIMIT_DB: f64 = 8.0;
/// The issue's bar for "brighter when faster": centroid at 1.5× velocity over as matched.
const MIN_BRIGHTNESS: f64 = 1.1;
/// The issue's budget: CPU seconds on one core per 5 s of recording matched.
const CPU_S_PER_5_S: f64 = 60.0;
/// Seconds of a clip `trundle match` matches by default (its middle).
const MATCH_SECONDS: f64 = 5.0;

/// Clips known to miss a bar today, with why (measured 28 Nov 2026 with the default match,
/// `--jobs 2`, on a shared 2-core machine; docs/guide/match.md shows the table). Every other
/// clip must pass every bar; when one of these comes inside, the test says so and it leaves
/// this list.
const KNOWN_OUTSIDE: [(&str, &str); 12] = [
    (
        "tyres on asphalt",
        "all four at 3 of 3 seeds, but not closer than shaped noise: noise already passes this steady clip's modulation and texture (2.75 dB, 0.77); the match reaches 2.48 dB but texture 0.79",
    ),
    (
        "metal scraping asphalt",
        "modulation 4.93 dB (shaped noise 4.54), texture 1.38 (a 1.3 s clip: its units are small), own spectrum 9.8 dB",
    ),
    (
        "hand saw",
        "push and pull read (3.5 strokes/s, returns at 46 %): texture 1.27, modulation 4.9 dB (its top bands swing with the strokes more than the recording's: spread 0.50 vs 0.30 above 5.6 kHz)",
    ),
    (
        "sawmill",
        "all four at 3 of 3 seeds (a rub with strokes pushed and pulled), but the model's own spectrum 13.4 dB (limit 8)",
    ),
    (
        "sawmill, steady",
        "modulation 5.3 dB, texture 2.2, kurtosis x1.95 at a seed, own spectrum 12.9 dB",
    ),
    (
        "grinding stone",
        "texture 1.43, modulation 3.5 dB at a seed",
    ),
    (
        "blade on a grindstone",
        "modulation 5.2 dB, texture 2.3 (shaped noise 1.77): a grindstone's turning swell over 9.3 s; kurtosis x8.2 at a seed",
    ),
    (
        "cart on a dirt track",
        "modulation 4.6 dB, texture 1.9: the slow events of the whole 4 s clip (faded in over 0.25 s)",
    ),
    (
        "bowed cello",
        "a pitched rub, the signal model's rub chosen over 8 friction starts: modulation 10.7 dB (shaped noise 10.3; the rub's low bands move 13-25 dB too much at 16-64 Hz), texture 1.9, own spectrum 8.6 dB",
    ),
    (
        "bowed viola",
        "a pitched rub, the signal model's roll chosen over 4 friction starts: spectrum 7.2 dB, modulation 7.4 dB (shaped noise 5.6), texture 1.6, own spectrum 12.6 dB",
    ),
    (
        "bowed cello, high",
        "a pitched rub: spectrum 3.7 dB, modulation 7.7 dB, texture 1.8 (not tonal by the cue: vibrato 1.3 %)",
    ),
    (
        "finger round a glass rim",
        "a pitched rub, friction chosen on its pitch (735 Hz) with strokes and micro, rendered after a 1 s pre-roll: 3 measures at every seed but texture 1.35 (shaped noise 1.16; its weak low bands bump on their own, the model's follow the tone), not brighter at 1.5x (x1.00)",
    ),
];

/// Of the whole corpus, how many clips meet each bar today (measured with [`KNOWN_OUTSIDE`]):
/// all four measures at every seed, closer than shaped noise, own spectrum within 8 dB, 1.5×
/// brighter. The test fails if a change to `match` loses any of them (the CPU budget is left
/// out: it depends on the machine).
const MEASURED: [usize; 4] = [3, 6, 8, 12];

/// One clip's verdicts.
struct Row {
    name: &'static str,
    /// Seconds of the whole clip.
    clip_s: f64,
    /// The match's own validation loss (its seeds, its excerpt).
    loss: f64,
    /// The action the match chose.
    action: String,
    /// The preset rendered at [`SEEDS`], against the whole clip.
    seeds: Vec<Comparison>,
    /// Shaped noise against the whole clip.
    noise: Comparison,
    /// The model's own spectrum (`body_eq=0`): mean over the seeds (dB).
    own_spectrum_db: f64,
    /// Centroid at 1.5× velocity over as matched (mean over the seeds).
    brightness: f64,
    /// CPU seconds the match took.
    cpu_s: f64,
    /// The CPU budget for this clip (s).
    cpu_budget_s: f64,
}

impl Row {
    fn all_four(&self) -> usize {
        self.seeds.iter().filter(|c| c.passed()).count()
    }

    fn beats_noise(&self) -> bool {
        self.seeds.iter().all(|c| {
            c.modulation.value < self.noise.modulation.value
                && c.texture.value < self.noise.texture.value
        })
    }

    /// Every bar, with the failures named.
    fn failures(&self) -> Vec<String> {
        let mut f = Vec::new();
        if self.all_four() < self.seeds.len() {
            f.push(format!(
                "all four at {} of {} seeds",
                self.all_four(),
                self.seeds.len()
            ));
        }
        if !self.beats_noise() {
            f.push("not closer than shaped noise on modulation and texture".into());
        }
        if self.own_spectrum_db > OWN_SPECTRUM_LIMIT_DB {
            f.push(format!(
                "own spectrum {:.1} dB (limit {OWN_SPECTRUM_LIMIT_DB})",
                self.own_spectrum_db
            ));
        }
        if self.brightness < MIN_BRIGHTNESS {
            f.push(format!("1.5× velocity centroid ×{:.2}", self.brightness));
        }
        if self.cpu_s > self.cpu_budget_s {
            f.push(format!(
                "{:.0} CPU s (budget {:.0})",
                self.cpu_s, self.cpu_budget_s
            ));
        }
        f
    }
}

fn env(name: &str) -> Option<String> {
    std::env::var(name).ok().filter(|s| !s.trim().is_empty())
}

/// The binary under test (`TRUNDLE_MATCH_BIN` or the one built with the tests).
fn trundle() -> PathBuf {
    env("TRUNDLE_MATCH_BIN").map_or_else(trundle_test_support::cli::bin, PathBuf::from)
}

/// Run `trundle args…` in `dir`; its exit code and standard output (panics naming the
/// command and its error output on a code not in `codes`).
fn run(dir: &Path, args: &[&str], codes: &[i32]) -> (i32, String) {
    let o = Command::new(trundle())
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the trundle binary runs");
    let code = o.status.code().unwrap_or(-1);
    assert!(
        codes.contains(&code),
        "trundle {args:?} exited {code}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    (code, String::from_utf8_lossy(&o.stdout).into_owned())
}

/// CPU seconds of this process's waited-for children (Linux `/proc/self/stat` fields
/// cutime + cstime, in clock ticks of 1/100 s); `None` elsewhere.
fn children_cpu_s() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which is in parentheses and may hold spaces).
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split(' ').collect();
    // Field 16 (cutime) and 17 (cstime) of `proc(5)`; `rest` starts at field 3.
    let ticks = f.get(13)?.parse::<f64>().ok()? + f.get(14)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// Spectral centroid (Hz) of `x`: power-weighted mean frequency of a Welch spectrum (Hann
/// frames of 4096 samples, half overlapping), the textbook definition.
fn centroid_hz(x: &[f64], fs: f64) -> f64 {
    let n = 4096usize.min(x.len().next_power_of_two() / 2).max(64);
    let power = trundle_dsp::analysis::stft::welch_power(x, n);
    let (mut num, mut den) = (0.0, 0.0);
    for (k, p) in power.iter().enumerate() {
        num += k as f64 * fs / n as f64 * p;
        den += p;
    }
    num / den.max(1e-300)
}

/// Render the preset `m.json` in `dir` at `seed`, as long and at the rate of the clip,
/// with `sets` on top; the mono samples.
fn render(dir: &Path, t: &Texture, seed: u32, sets: &[String], name: &str) -> Vec<f64> {
    let seconds = format!("{}", t.seconds());
    let rate = t.sample_rate_hz.to_string();
    let seed = seed.to_string();
    let mut args = vec![
        "render",
        "--preset",
        "m.json",
        "--seconds",
        &seconds,
        "--sample-rate",
        &rate,
        "--seed",
        &seed,
        "--channels",
        "1",
        "--force",
        "-o",
        name,
    ];
    for s in sets {
        args.push("--set");
        args.push(s);
    }
    run(dir, &args, &[0]);
    read_wav_mono(&dir.join(name)).0
}

/// Match `clip` in `dir` and judge the preset.
fn measure(dir: &Path, clip: &Clip, jobs: usize, extra: &[String]) -> Row {
    let t = load(clip).unwrap_or_else(|e| panic!("{e}"));
    let fs = f64::from(t.sample_rate_hz);
    let x = t.to_f64();
    write_wav(&dir.join("clip.wav"), t.sample_rate_hz, 1, &x);
    let jobs_s = jobs.to_string();
    let mut args = vec![
        "match", "clip.wav", "-o", "m.json", "--json", "--force", "--jobs", &jobs_s,
    ];
    args.extend(extra.iter().map(String::as_str));
    let (cpu0, wall) = (children_cpu_s(), Instant::now());
    let (_, out) = run(dir, &args, &[0, 3]);
    let wall_s = wall.elapsed().as_secs_f64();
    let cpu_s = match (cpu0, children_cpu_s()) {
        (Some(a), Some(b)) => b - a,
        // No per-process clock: count every thread busy the whole time.
        _ => wall_s * jobs as f64,
    };
    let report: serde_json::Value = serde_json::from_str(&out).expect("match --json");
    let preset: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("m.json")).unwrap()).unwrap();
    let velocity = preset["params"]["velocity"].as_f64().expect("a velocity");
    let fast = vec![format!("velocity={}", (1.5 * velocity).min(1.0))];
    let own = vec!["body_eq=0".to_string()];
    let (mut seeds, mut own_db, mut bright) = (Vec::new(), 0.0, 0.0);
    for &s in &SEEDS {
        let y = render(dir, &t, s, &[], &format!("seed{s}.wav"));
        let c = compare(&x, fs, &y, fs).expect("a render compares");
        let y0 = render(dir, &t, s, &own, &format!("own{s}.wav"));
        own_db += compare(&x, fs, &y0, fs).unwrap().spectrum.value / SEEDS.len() as f64;
        let yf = render(dir, &t, s, &fast, &format!("fast{s}.wav"));
        bright += centroid_hz(&yf, fs) / centroid_hz(&y, fs) / SEEDS.len() as f64;
        seeds.push(c);
    }
    let noise = shaped_noise(&x, x.len(), NOISE_SEED);
    let matched_s = t.seconds().min(MATCH_SECONDS);
    Row {
        name: clip.name,
        clip_s: t.seconds(),
        loss: report["loss"].as_f64().unwrap_or(f64::NAN),
        action: report["action"].as_str().unwrap_or("?").to_string(),
        seeds,
        noise: compare(&x, fs, &noise, fs).unwrap(),
        own_spectrum_db: own_db,
        brightness: bright,
        cpu_s,
        cpu_budget_s: CPU_S_PER_5_S * matched_s / MATCH_SECONDS,
    }
}

/// The README's table.
fn table(rows: &[Row]) -> String {
    let worst = |r: &Row, f: fn(&Comparison) -> f64| {
        r.seeds.iter().map(f).fold(f64::NEG_INFINITY, f64::max)
    };
    let mut s = String::from(
        "| clip | s | action | match loss | all four (of 3 seeds) | measures per seed | spectrum dB | modulation dB (noise) | texture (noise) | kurtosis × | crest dB | own spectrum dB | 1.5× centroid | CPU s |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let per: Vec<String> = r
            .seeds
            .iter()
            .map(|c| c.measures_passed().to_string())
            .collect();
        let kmax = r
            .seeds
            .iter()
            .map(|c| c.kurtosis.value)
            .max_by(|a, b| a.ln().abs().total_cmp(&b.ln().abs()))
            .unwrap_or(f64::NAN);
        let cmax = r
            .seeds
            .iter()
            .map(|c| c.crest.value)
            .max_by(|a, b| a.abs().total_cmp(&b.abs()))
            .unwrap_or(f64::NAN);
        s += &format!(
            "| {} | {:.1} | {} | {:.2} | {} | {} | {:.2} | {:.2} ({:.2}) | {:.2} ({:.2}) | ×{:.2} | {:+.1} | {:.1} | ×{:.2} | {:.0} |\n",
            r.name,
            r.clip_s,
            r.action,
            r.loss,
            r.all_four(),
            per.join(" "),
            worst(r, |c| c.spectrum.value),
            worst(r, |c| c.modulation.value),
            r.noise.modulation.value,
            worst(r, |c| c.texture.value),
            r.noise.texture.value,
            kmax,
            cmax,
            r.own_spectrum_db,
            r.brightness,
            r.cpu_s,
        );
    }
    let count = |f: &dyn Fn(&Row) -> bool| rows.iter().filter(|r| f(r)).count();
    s += &format!(
        "\nof {}: all four at every seed {}; closer than shaped noise {}; own spectrum within {OWN_SPECTRUM_LIMIT_DB} dB {}; 1.5× brighter {}; within the CPU budget {}\n",
        rows.len(),
        count(&|r| r.all_four() == r.seeds.len()),
        count(&|r| r.beats_noise()),
        count(&|r| r.own_spectrum_db <= OWN_SPECTRUM_LIMIT_DB),
        count(&|r| r.brightness >= MIN_BRIGHTNESS),
        count(&|r| r.cpu_s <= r.cpu_budget_s),
    );
    s
}

#[test]
#[ignore = "needs Debian's torcs-data, widelands-data, lincity-ng-data, fluid-soundfont-gm and cube2-data (apt-get install torcs-data widelands-data lincity-ng-data fluid-soundfont-gm cube2-data)"]
fn every_corpus_clip_is_matched_within_the_bar() {
    let jobs = env("TRUNDLE_MATCH_JOBS")
        .map(|j| j.parse::<usize>().expect("TRUNDLE_MATCH_JOBS: a number"))
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let extra: Vec<String> = env("TRUNDLE_MATCH_ARGS")
        .map(|a| a.split_whitespace().map(String::from).collect())
        .unwrap_or_default();
    let only: Vec<String> = env("TRUNDLE_MATCH_CLIPS")
        .map(|c| c.split(',').map(|w| w.trim().to_lowercase()).collect())
        .unwrap_or_default();
    let keep = env("TRUNDLE_MATCH_KEEP").map(PathBuf::from);
    let s = scratch("corpus");
    let mut rows = Vec::new();
    for clip in CORPUS.iter().filter(|c| {
        only.is_empty()
            || only
                .iter()
                .any(|w| c.name.to_lowercase().contains(w.as_str()))
    }) {
        let dir = match &keep {
            Some(k) => k.join(clip.name.replace([' ', ','], "_")),
            None => s.path().join(clip.name.replace([' ', ','], "_")),
        };
        std::fs::create_dir_all(&dir).unwrap();
        let r = measure(&dir, clip, jobs, &extra);
        println!(
            "{}: loss {:.2}, {} of 3 seeds all four, own spectrum {:.1} dB, ×{:.2} at 1.5×, {:.0} CPU s{}",
            r.name,
            r.loss,
            r.all_four(),
            r.own_spectrum_db,
            r.brightness,
            r.cpu_s,
            if r.failures().is_empty() {
                String::new()
            } else {
                format!(": {}", r.failures().join("; "))
            }
        );
        rows.push(r);
    }
    assert!(!rows.is_empty(), "no clip matches TRUNDLE_MATCH_CLIPS");
    let t = table(&rows);
    println!("{t}");
    let known = |name: &str| KNOWN_OUTSIDE.iter().any(|(k, _)| *k == name);
    for r in rows
        .iter()
        .filter(|r| known(r.name) && r.failures().is_empty())
    {
        println!(
            "now inside every bar: {} (take it off KNOWN_OUTSIDE)",
            r.name
        );
    }
    let failed: Vec<String> = rows
        .iter()
        .filter(|r| !known(r.name) && !r.failures().is_empty())
        .map(|r| format!("{}: {}", r.name, r.failures().join("; ")))
        .collect();
    assert!(
        failed.is_empty(),
        "outside the bar:\n{}\n{t}",
        failed.join("\n")
    );
    if rows.len() == CORPUS.len() {
        let count = |f: &dyn Fn(&Row) -> bool| rows.iter().filter(|r| f(r)).count();
        let now = [
            count(&|r| r.all_four() == r.seeds.len()),
            count(&|r| r.beats_noise()),
            count(&|r| r.own_spectrum_db <= OWN_SPECTRUM_LIMIT_DB),
            count(&|r| r.brightness >= MIN_BRIGHTNESS),
        ];
        for (k, (n, m)) in now.iter().zip(MEASURED).enumerate() {
            assert!(*n >= m, "bar {k}: {n} clips, {m} measured before\n{t}");
        }
    }
}
