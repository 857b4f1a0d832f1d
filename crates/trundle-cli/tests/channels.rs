//! Channels and the safety limiter through `trundle render`: stereo by default with the right
//! length in every format, mono as the mean of the stereo channels, the limiter keeping the
//! render time-aligned, the force staying mono and raw.

use std::fs;
use trundle_test_support::cli::{number_before, ok};
use trundle_test_support::levels::{ceiling, channels, peak, peak_db};
use trundle_test_support::scratch::scratch;
use trundle_test_support::wav::read_wav;

#[test]
fn stereo_is_the_default_with_the_right_length_in_every_format() {
    let d = scratch("stereo");
    for (format, bits) in [("pcm24", 24), ("pcm16", 16), ("f32", 32)] {
        let name = format!("{format}.wav");
        let line = ok(
            &d,
            &[
                "render",
                "--seconds",
                "0.37",
                "--sample-rate",
                "22050",
                "--format",
                format,
                "-o",
                &name,
            ],
        );
        assert!(line.contains("(sound, stereo)"), "{line}");
        let (spec, x) = read_wav(&d.join(&name));
        assert_eq!((spec.channels, spec.bits_per_sample), (2, bits), "{format}");
        // round(0.37 × 22050) = 8159 frames (8158.5 rounds away from zero).
        assert_eq!(x.len(), 2 * 8159, "{format}");
        // Normalized with one gain: the louder channel peaks at -1 dBFS.
        let p = channels(&x, 2)
            .iter()
            .map(|c| peak_db(c))
            .fold(f64::MIN, f64::max);
        assert!((p + 1.0).abs() < 0.01, "{format}: peak {p}");
    }
    // --channels 2 is the default spelled out: the same bytes.
    ok(
        &d,
        &[
            "render",
            "--seconds",
            "0.37",
            "--sample-rate",
            "22050",
            "--format",
            "f32",
            "--channels",
            "2",
            "-o",
            "two.wav",
        ],
    );
    assert_eq!(
        fs::read(d.join("two.wav")).unwrap(),
        fs::read(d.join("f32.wav")).unwrap()
    );
}

#[test]
fn mono_is_the_mean_of_the_stereo_channels() {
    // --channels 1 renders the voice's mono mix (Voice::process), which the core defines as
    // (L + R)/2 of Voice::process_stereo. Calibrated, limiter off and float, so no level
    // stage differs between the two renders (the stereo-linked limiter would see other
    // peaks); the guard must not act either. Tolerance: L and R are f32 roundings of
    // mid ± side, so (L + R)/2 is the mid within 2⁻²⁵·(|L| + |R|) (times 1.001 for the
    // second-order term); 10⁻³⁰ for the flush of tiny samples. With the mode-shape object
    // (main, e7a8141) the worst frame measured 0.995 of that bound on the two wide scenes.
    // A scene with automation and one with extra balls go through the event loop's notes
    // and lanes; an off-centre listening point at full width makes L and R differ.
    let d = scratch("mono");
    let scenes: [(&str, &str, &[&str]); 5] = [
        ("default", "default", &[]),
        ("morph", "roll-scrape-rub-morph", &[]),
        ("balls", "marbles-spilled", &[]),
        ("plate", "ball-across-metal-plate", &[]),
        (
            "wide",
            "default",
            &["--set", "listen_x=0.6", "--set", "width=1"],
        ),
    ];
    for (preset, stem, extra) in scenes {
        let render = |channels: &str| {
            let name = format!("{preset}-{channels}.wav");
            let line = ok(
                &d,
                &[
                    &[
                        "render",
                        "--preset",
                        stem,
                        "--seconds",
                        "1.5",
                        "--no-normalize",
                        "--set",
                        "limiter=off",
                        "--format",
                        "f32",
                        "--channels",
                        channels,
                        "-o",
                        &name,
                    ][..],
                    extra,
                ]
                .concat(),
            );
            assert!(line.contains("never-clip guard bent 0 frames"), "{line}");
            let (spec, x) = read_wav(&d.join(&name));
            assert_eq!(spec.channels.to_string(), channels);
            (line, x)
        };
        let (mono_line, mono) = render("1");
        let (stereo_line, stereo) = render("2");
        assert!(mono_line.contains("(sound, mono)"), "{mono_line}");
        assert_eq!(mono.len() * 2, stereo.len(), "{preset}");
        assert_eq!(
            number_before(&mono_line, "impacts"),
            number_before(&stereo_line, "impacts"),
            "{preset}: the same scene"
        );
        let mut worst = 0f64;
        for (i, &m) in mono.iter().enumerate() {
            let (l, r) = (stereo[2 * i], stereo[2 * i + 1]);
            let err = (m - (l + r) / 2.0).abs();
            let tol = (l.abs() + r.abs()) * 2f64.powi(-25) * 1.001 + 1e-30;
            assert!(err <= tol, "{preset} frame {i}: mono {m}, L {l}, R {r}");
            worst = worst.max(err);
        }
        assert!(peak(&mono) > 0.01, "{preset}: not silent");
        let differ = (0..mono.len())
            .filter(|&i| stereo[2 * i] != stereo[2 * i + 1])
            .count();
        println!(
            "{preset}: largest |mono - (L+R)/2| = {worst:e}, L != R in {differ} of {} frames",
            mono.len()
        );
    }
}

#[test]
fn the_safety_limiter_keeps_the_render_time_aligned() {
    let d = scratch("latency");
    let render = |name: &str, extra: &[&str]| {
        let line = ok(
            &d,
            &[
                &[
                    "render",
                    "--seconds",
                    "1",
                    "--no-normalize",
                    "--format",
                    "f32",
                    "-o",
                    name,
                ][..],
                extra,
            ]
            .concat(),
        );
        let (_, x) = read_wav(&d.join(name));
        (line, x)
    };
    // A quiet scene (the default, peaks under -1 dBFS): the limiter never acts, so with its
    // latency compensated the file is the limiter-off file sample for sample — in stereo and
    // mono. A shift by one frame, or a missing tail, would differ.
    for ch in ["2", "1"] {
        let (on_line, on) = render(&format!("on{ch}.wav"), &["--channels", ch]);
        let (_, off) = render(
            &format!("off{ch}.wav"),
            &["--channels", ch, "--set", "limiter=off"],
        );
        assert!(
            on_line.contains("safety limiter touched 0 frames"),
            "{on_line}"
        );
        assert!(
            peak(&off) < ceiling() && peak(&off) > 0.1,
            "quiet, not silent: {}",
            peak(&off)
        );
        assert_eq!(on.len(), off.len());
        assert!(on == off, "--channels {ch}: limiter on and off differ");
        // The last frames came out of the delay line too (they are not the flush's zeros).
        assert!(on[on.len() - 200..].iter().any(|v| *v != 0.0));
    }
    // A hot scene, where the limiter acts: its gain is slow and positive, so the limited file
    // correlates best with the unlimited one at lag 0, not at the limiter's latency (72
    // frames at 48 kHz).
    let hot = ["--set", "gain_db=12", "--channels", "1"];
    let (line, on) = render("hot-on.wav", &hot);
    assert!(number_before(&line, "frames (") > 0, "{line}");
    let (_, off) = render(
        "hot-off.wav",
        &[&hot[..], &["--set", "limiter=off"]].concat(),
    );
    let corr = |lag: i64| -> f64 {
        (0..on.len() as i64)
            .filter_map(|i| {
                let j = i + lag;
                (0..off.len() as i64)
                    .contains(&j)
                    .then(|| on[i as usize] * off[j as usize])
            })
            .sum()
    };
    let best = (-100..=100)
        .max_by(|&a, &b| corr(a).total_cmp(&corr(b)))
        .unwrap();
    assert_eq!(best, 0, "the limited render is shifted by {best} frames");
}

#[test]
fn force_only_stays_mono_and_raw() {
    // The force is one signal: mono by default, written raw (no safety limiter, which would
    // reshape the impact peaks `analyze` measures). `--channels 2` puts it on both channels.
    let d = scratch("force-mono");
    let base = [
        "render",
        "--seconds",
        "0.5",
        "--force-only",
        "--no-normalize",
        "--format",
        "f32",
    ];
    let line = ok(&d, &[&base[..], &["-o", "f.wav"]].concat());
    assert!(line.contains("(force, mono)"), "{line}");
    assert!(line.contains("force written raw"), "{line}");
    let (spec, f) = read_wav(&d.join("f.wav"));
    assert_eq!((spec.channels, f.len()), (1, 24_000));
    // The scene's limiter setting does not change the force.
    ok(
        &d,
        &[&base[..], &["--set", "limiter=off", "-o", "g.wav"]].concat(),
    );
    assert_eq!(
        fs::read(d.join("f.wav")).unwrap(),
        fs::read(d.join("g.wav")).unwrap()
    );
    ok(
        &d,
        &[&base[..], &["--channels", "2", "-o", "f2.wav"]].concat(),
    );
    let (spec, f2) = read_wav(&d.join("f2.wav"));
    assert_eq!(spec.channels, 2);
    let [l, r] = <[Vec<f64>; 2]>::try_from(channels(&f2, 2)).unwrap();
    assert_eq!(l, f);
    assert_eq!(r, f);
}
