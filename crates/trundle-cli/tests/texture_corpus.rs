//! The calibration of `trundle compare` on real textures (issue #25): every clip of the
//! texture corpus (`trundle_test_support::texture_corpus`: tyres, saws, grinding, a dirt
//! track, bowed strings, …) passes all four measures against its own other half, and fails
//! against every other clip's half; noise shaped to each clip's long-term spectrum (the
//! issue's baseline) passes what it is expected to pass and no more (per clip, as measured:
//! [`NOISE_PASSES`]). It prints the tables `docs/corpus.md` shows:
//!
//! ```sh
//! cargo test -p trundle-cli --test texture_corpus -- --ignored --nocapture
//! ```

use std::collections::HashMap;
use trundle_dsp::analysis::compare::{compare_profiles, profile, Comparison, Profile, TOP_HZ};
use trundle_test_support::texture_corpus::{load, shaped_noise, Texture, CORPUS};

/// Seed of the shaped noise.
const NOISE_SEED: u64 = 25;

/// What shaped noise passes against each clip's first half, as measured (spectrum,
/// modulation, texture, impulsiveness; seed [`NOISE_SEED`]). Same spectrum by construction
/// (it misses on three clips whose halves differ most or whose partials are sparse); it fails
/// the texture on 11 of 13 and the modulation on 11 of 13: the two steadiest clips (tyres,
/// metal scraping) are as flat as noise in their envelopes' swells, and the glass's band
/// envelopes (its tone's swells as the finger circles) have statistics a noise shares. The
/// issue asks of a match that it be closer than this noise on modulation and texture.
const NOISE_PASSES: [(&str, [bool; 4]); 13] = [
    ("tyres on asphalt", [true, true, false, true]),
    ("metal scraping asphalt", [true, true, false, true]),
    ("hand saw", [true, false, false, false]),
    ("sawmill", [false, false, false, false]),
    ("sawmill, steady", [true, false, false, true]),
    ("grinding stone", [true, false, false, true]),
    ("blade on a grindstone", [true, false, false, false]),
    ("cart on a dirt track", [true, false, false, false]),
    ("traffic", [true, false, false, true]),
    ("bowed cello", [true, false, false, true]),
    ("bowed viola", [false, false, true, true]),
    ("bowed cello, high", [false, false, false, true]),
    ("finger round a glass rim", [true, false, true, true]),
];

/// The four verdicts of a comparison.
fn verdicts(c: &Comparison) -> [bool; 4] {
    [
        c.spectrum.passed,
        c.modulation.passed,
        c.texture.passed,
        c.impulsiveness_passed(),
    ]
}

fn row(c: &Comparison) -> String {
    let mark = |p: bool| if p { "" } else { " ✗" };
    format!(
        "{:.2}{} | {:.2}{} | {:.2}{} | ×{:.2}, {:+.1} dB{}",
        c.spectrum.value,
        mark(c.spectrum.passed),
        c.modulation.value,
        mark(c.modulation.passed),
        c.texture.value,
        mark(c.texture.passed),
        c.kurtosis.value,
        c.crest.value,
        mark(c.impulsiveness_passed()),
    )
}

/// Profiles of each clip's halves, analysed up to each top frequency they are compared at.
struct Profiles<'a> {
    clips: &'a [Texture],
    cache: HashMap<(usize, usize, u64), Profile>,
}

impl Profiles<'_> {
    fn top_hz(&self, a: usize, b: usize) -> f64 {
        let ny = |i: usize| 0.5 * f64::from(self.clips[i].sample_rate_hz);
        ny(a).min(ny(b)).min(TOP_HZ)
    }

    fn get(&mut self, clip: usize, half: usize, top_hz: f64) -> Profile {
        let t = &self.clips[clip];
        self.cache
            .entry((clip, half, top_hz.to_bits()))
            .or_insert_with(|| {
                let (a, b) = t.halves();
                let x = if half == 0 { a } else { b };
                profile(&x, f64::from(t.sample_rate_hz), top_hz, "clip")
                    .unwrap_or_else(|e| panic!("{e}"))
            })
            .clone()
    }
}

#[test]
#[ignore = "needs Debian's torcs-data, widelands-data, lincity-ng-data, fluid-soundfont-gm and cube2-data (apt-get install torcs-data widelands-data lincity-ng-data fluid-soundfont-gm cube2-data)"]
fn every_clip_passes_its_own_half_and_fails_every_other() {
    let clips: Vec<Texture> = CORPUS
        .iter()
        .map(|c| load(c).unwrap_or_else(|e| panic!("{e}")))
        .collect();
    let mut p = Profiles {
        clips: &clips,
        cache: HashMap::new(),
    };
    let n = clips.len();
    let mut table = String::from(
        "| clip | kind | s | first half vs second: spectrum dB | modulation dB | texture | impulsiveness | shaped noise: spectrum dB | modulation dB | texture | impulsiveness |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut own_fail = Vec::new();
    let mut noise_passes = Vec::new();
    for (i, clip) in CORPUS.iter().enumerate() {
        let top = p.top_hz(i, i);
        let own = compare_profiles(p.get(i, 0, top), p.get(i, 1, top));
        if !own.passed() {
            own_fail.push(format!("{}: {}", clip.name, row(&own)));
        }
        let t = &clips[i];
        let x = t.to_f64();
        let half = x.len() / 2;
        let noise = shaped_noise(&x, half, NOISE_SEED);
        let np = profile(&noise, f64::from(t.sample_rate_hz), top, "noise")
            .unwrap_or_else(|e| panic!("{e}"));
        let nc = compare_profiles(p.get(i, 0, top), np);
        noise_passes.push((clip.name, verdicts(&nc)));
        table.push_str(&format!(
            "| {} | {} | {:.1} | {} | {} |\n",
            clip.name,
            clip.kind.label(),
            t.seconds(),
            row(&own),
            row(&nc)
        ));
    }
    // Every clip's first half against every other clip's second half.
    let mut cross_pass = Vec::new();
    let mut per_measure = [0usize; 4];
    for (a, clip_a) in CORPUS.iter().enumerate() {
        for b in (0..n).filter(|&b| b != a) {
            let top = p.top_hz(a, b);
            let c = compare_profiles(p.get(a, 0, top), p.get(b, 1, top));
            for (k, v) in verdicts(&c).iter().enumerate() {
                per_measure[k] += usize::from(*v);
            }
            if c.passed() {
                cross_pass.push(format!(
                    "{} vs {}: {}",
                    clip_a.name,
                    CORPUS[b].name,
                    row(&c)
                ));
            }
        }
    }
    let pairs = n * (n - 1);
    table.push_str(&format!(
        "\nEvery clip against every other ({pairs} pairs): {} pass all four; spectrum passes {}, modulation {}, texture {}, impulsiveness {}.\n",
        cross_pass.len(),
        per_measure[0],
        per_measure[1],
        per_measure[2],
        per_measure[3]
    ));
    println!("{table}");
    println!("pairs passing all four: {cross_pass:#?}");
    println!("noise passes: {noise_passes:?}");
    assert!(
        own_fail.is_empty(),
        "clips failing their own other half:\n{}",
        own_fail.join("\n")
    );
    assert!(
        cross_pass.is_empty(),
        "clips passing against another clip:\n{}",
        cross_pass.join("\n")
    );
    for (name, v) in &noise_passes {
        let expected = NOISE_PASSES.iter().find(|(k, _)| k == name).map(|e| e.1);
        assert_eq!(
            expected,
            Some(*v),
            "{name}: shaped noise passes {v:?} (spectrum, modulation, texture, impulsiveness)"
        );
    }
}
