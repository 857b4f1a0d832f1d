//! The fast textures of docs/MODEL.md "High band and crackle": micro-roughness (the contact's
//! high band), crackle (a sparse loud layer) and grit in every action, measured on short
//! renders of the whole voice.

use trundle_dsp::params::ParamId;
use trundle_dsp::Params;
use trundle_dsp::Voice;
use trundle_test_support::bands::third_octave_energy_between;
use trundle_test_support::scene::{render, render_at, render_frames, render_voice, FS};

/// The default scene (a wooden ball rolling on a wooden table) with `changes`.
fn scene(changes: &[(ParamId, f64)]) -> Params {
    let mut p = Params::default();
    for &(id, v) in changes {
        p.set(id, v).expect("in range");
    }
    p
}

/// The action disk's rub anchor (angle 0).
const RUB: [(ParamId, f64); 2] = [(ParamId::ActionX, 1.0), (ParamId::ActionY, 0.0)];

/// Level (dB) of the third-octave bands centred 4–16 kHz re the whole 50 Hz–16 kHz band.
fn high_re_total_db(x: &[f32]) -> f64 {
    let e = third_octave_energy_between(x, FS, 50.0, 16_000.0);
    let high = third_octave_energy_between(x, FS, 4_000.0, 16_000.0);
    10.0 * (high.iter().sum::<f64>() / e.iter().sum::<f64>()).log10()
}

/// Spectral centroid (Hz) from the third-octave energies 50 Hz–16 kHz.
fn centroid_hz(x: &[f32]) -> f64 {
    let c = trundle_test_support::bands::centres_hz();
    let e = third_octave_energy_between(x, FS, 50.0, 16_000.0);
    c.iter().zip(&e).map(|(f, e)| f * e).sum::<f64>() / e.iter().sum::<f64>()
}

/// Signal kurtosis (3 for a Gaussian).
fn kurtosis(x: &[f32]) -> f64 {
    let n = x.len() as f64;
    let m = x.iter().map(|&v| v as f64).sum::<f64>() / n;
    let (m2, m4) = x.iter().fold((0.0, 0.0), |(a, b), &v| {
        let d = v as f64 - m;
        (a + d * d, b + d * d * d * d)
    });
    (m4 / n) / (m2 / n).powi(2)
}

/// `seconds` of `p` with the micro force's direct share on or off.
fn render_direct(p: &Params, seconds: f64, direct: bool) -> Vec<f32> {
    let mut v = Voice::new(FS, p);
    v.set_micro_direct(direct);
    render_voice(&mut v, seconds, 4096)
}

#[test]
#[ignore = "a report: prints the numbers the constants were chosen with"]
fn report_layers() {
    for (name, action) in [("roll", &[][..]), ("rub", &RUB[..])] {
        for v in [0.4, 0.6] {
            let mut ch = action.to_vec();
            ch.push((ParamId::Velocity, v));
            ch.push((ParamId::Micro, 0.5));
            let p = scene(&ch);
            let (a, b) = (render_direct(&p, 3.0, true), render_direct(&p, 3.0, false));
            let c = trundle_test_support::bands::centres_hz();
            let (ea, eb) = (
                third_octave_energy_between(&a, FS, 50.0, 16_000.0),
                third_octave_energy_between(&b, FS, 50.0, 16_000.0),
            );
            let line: Vec<String> = c
                .iter()
                .zip(ea.iter().zip(&eb))
                .filter(|(f, _)| **f >= 2000.0)
                .map(|(f, (x, y))| format!("{f:.0}:{:+.1}", 10.0 * (y / x).log10()))
                .collect();
            println!(
                "{name} V {v} micro 0.5, modes only vs with direct (dB per band): {}; >4k re total {:+.1} vs {:+.1}",
                line.join(" "),
                high_re_total_db(&b),
                high_re_total_db(&a)
            );
        }
    }
    for (name, action) in [("roll", &[][..]), ("rub", &RUB[..])] {
        for grit in [0.0, 0.8] {
            let mut ch = action.to_vec();
            ch.push((ParamId::Grit, grit));
            let x = render(&scene(&ch), 4.0);
            println!("{name} grit {grit}: kurtosis {:.2}", kurtosis(&x[4800..]));
        }
        for (crackle, level) in [
            (0.0, 0.5),
            (0.3, 0.5),
            (0.6, 0.5),
            (1.0, 0.5),
            (0.6, 0.3),
            (0.6, 0.8),
        ] {
            let mut ch = action.to_vec();
            ch.push((ParamId::Crackle, crackle));
            ch.push((ParamId::CrackleLevel, level));
            let k: Vec<String> = [1u64, 2, 3]
                .iter()
                .map(|&seed| {
                    let mut p = scene(&ch);
                    p.set(ParamId::Seed, seed as f64).unwrap();
                    let x = render(&p, 4.0);
                    format!("{:.2}", kurtosis(&x[4800..]))
                })
                .collect();
            println!(
                "{name} crackle {crackle} level {level}: kurtosis {}",
                k.join(" ")
            );
        }
    }
}

#[test]
#[ignore = "a report: prints the numbers the constants were chosen with"]
fn report() {
    for (name, action) in [("roll", &[][..]), ("rub", &RUB[..])] {
        for v in [0.4, 0.6, 0.9] {
            for micro in [0.0, 0.25, 0.5, 1.0] {
                let mut ch = action.to_vec();
                ch.push((ParamId::Velocity, v));
                ch.push((ParamId::Micro, micro));
                let x = render(&scene(&ch), 3.0);
                println!(
                    "{name} V {v} micro {micro}: >4k {:+.1} dB re total, centroid {:.0} Hz, kurtosis {:.2}",
                    high_re_total_db(&x),
                    centroid_hz(&x),
                    kurtosis(&x[4800..])
                );
            }
        }
    }
}

/// Median over seeds 1–3 of `f` of `seconds` of `changes` (a texture's statistics hang on
/// its rare events: one take is not a measure).
fn median_over_seeds(changes: &[(ParamId, f64)], seconds: f64, f: fn(&[f32]) -> f64) -> f64 {
    let mut v: Vec<f64> = (1..=3)
        .map(|seed| {
            let mut p = scene(changes);
            p.set(ParamId::Seed, seed as f64).unwrap();
            f(&render(&p, seconds)[4800..])
        })
        .collect();
    v.sort_by(f64::total_cmp);
    v[1]
}

/// Micro at 0.5 lifts a roll's level above 4 kHz (re its whole band) by 15–28 dB: measured
/// +24.2 dB at V 0.4 and +20.2 dB at V 0.6 (−34.5 → −10.3, −28.4 → −8.2), so the range
/// leaves ±4 dB of room on either side of V 0.5. The object's modes alone make a part of
/// it (+7…+12 dB measured), the directly radiated share the rest (+13 dB over the modes):
/// above its explicit modes the object has too few modes to pass a hiss.
#[test]
fn micro_lifts_the_band_above_4_khz() {
    let off = high_re_total_db(&render(&scene(&[]), 3.0));
    let p = scene(&[(ParamId::Micro, 0.5)]);
    let on = high_re_total_db(&render_direct(&p, 3.0, true));
    let modes = high_re_total_db(&render_direct(&p, 3.0, false));
    println!("above 4 kHz re total: off {off:.1}, modes only {modes:.1}, with direct {on:.1} dB");
    assert!((15.0..=28.0).contains(&(on - off)), "{off:.1} → {on:.1} dB");
    assert!(
        modes - off >= 4.0,
        "the modes alone: {off:.1} → {modes:.1} dB"
    );
    assert!(
        on - modes >= 8.0,
        "the direct share: {modes:.1} → {on:.1} dB"
    );
}

/// With micro on, a ball 1.5× as fast is brighter: the centroid rises ≥ 10 % from V 0.4 to
/// 0.6 (measured +60 % rolling, +113 % rubbing at micro 0.5; without micro +9 % rolling).
#[test]
fn micro_makes_a_faster_contact_brighter() {
    for action in [&[][..], &RUB[..]] {
        let at = |v: f64| {
            let mut ch = action.to_vec();
            ch.push((ParamId::Micro, 0.5));
            ch.push((ParamId::Velocity, v));
            centroid_hz(&render(&scene(&ch), 3.0))
        };
        let (slow, fast) = (at(0.4), at(0.6));
        println!("centroid {slow:.0} → {fast:.0} Hz");
        assert!(fast >= 1.1 * slow, "{slow:.0} → {fast:.0} Hz");
    }
}

/// A gravel roll (roughness 1, V 0.6, micro 0.5) reaches 16 kHz: its 16 kHz third-octave
/// band within 10 dB of its 4 kHz band (the micro band's top is 0.6/22.5 µm, capped at
/// 0.45·f_s = 21.6 kHz; the direct share is flat there). Without micro the 16 kHz band is
/// far under (the pulse width caps the band).
#[test]
fn a_gravel_roll_reaches_16_khz() {
    let band = |micro: f64| {
        let x = render(
            &scene(&[
                (ParamId::Roughness, 1.0),
                (ParamId::Velocity, 0.6),
                (ParamId::Micro, micro),
            ]),
            2.0,
        );
        let e = third_octave_energy_between(&x, FS, 4_000.0, 16_000.0);
        10.0 * (e[6] / e[0]).log10()
    };
    let (off, on) = (band(0.0), band(0.5));
    println!("16 kHz band re 4 kHz band: off {off:.1} dB, micro {on:.1} dB");
    assert!(on >= -10.0, "{on:.1} dB");
    assert!(on - off >= 10.0, "{off:.1} → {on:.1} dB");
}

/// Crackle makes a rub heavy-tailed: median kurtosis over three seeds from 3.3 (measured)
/// to within 3.5–8 at crackle 0.6 (the real rubs and scrapes 3.6–4.7, a stylus 7.6),
/// and more at crackle 1 than at 0.3.
#[test]
fn crackle_gives_a_rub_heavy_tails() {
    let k = |crackle: f64| {
        let mut ch = RUB.to_vec();
        ch.push((ParamId::Crackle, crackle));
        median_over_seeds(&ch, 4.0, kurtosis)
    };
    let (none, low, mid, high) = (k(0.0), k(0.3), k(0.6), k(1.0));
    println!("rub kurtosis: crackle 0 {none:.2}, 0.3 {low:.2}, 0.6 {mid:.2}, 1 {high:.2}");
    assert!(none < 3.5, "{none:.2}");
    assert!((3.5..=8.0).contains(&mid), "{mid:.2}");
    assert!(high > low, "{low:.2} → {high:.2}");
}

/// Grit acts in a rub (it did nothing there: kurtosis 3.64 → 3.63 at grit 0.8 in the
/// issue): its grains lift the median kurtosis by at least 0.15 (measured 3.28 → 3.55, +0.27;
/// +0.20 with grains struck at twice a rolled grain's strength). At grit 0.8 the grains come
/// 160 times a second and overlap in the object's ringing, which keeps the sum near Gaussian:
/// heavy tails are crackle's job (above).
#[test]
fn grit_acts_in_a_rub() {
    let k = |grit: f64| {
        let mut ch = RUB.to_vec();
        ch.push((ParamId::Grit, grit));
        median_over_seeds(&ch, 4.0, kurtosis)
    };
    let (clean, gritty) = (k(0.0), k(0.8));
    println!("rub kurtosis: grit 0 {clean:.2}, grit 0.8 {gritty:.2}");
    assert!(gritty - clean >= 0.15, "{clean:.2} → {gritty:.2}");
}

/// The textures allocate nothing while processing (the voice runs them inside the guard).
#[test]
fn textures_do_not_allocate() {
    let p = scene(&[
        (ParamId::Micro, 1.0),
        (ParamId::Crackle, 1.0),
        (ParamId::Grit, 1.0),
        (ParamId::ActionX, 1.0),
        (ParamId::ActionY, 0.0),
    ]);
    let mut v = Voice::new(FS, &p);
    let mut out = vec![0f32; 48_000];
    let n = trundle_test_support::alloc_guard::allocations_during(|| {
        for c in out.chunks_mut(512) {
            v.process(c);
        }
    });
    assert_eq!(n, 0);
    assert!(out.iter().all(|x| x.is_finite()));
}

/// micro = 0 and crackle = 0 change nothing: the voice is the one without the stage, bit for bit (the
/// goldens hold every preset to it; here the default scene and a rub at once).
#[test]
fn micro_off_is_bit_identical_to_no_micro() {
    for action in [&[][..], &RUB[..]] {
        let a = render(&scene(action), 0.5);
        let mut ch = action.to_vec();
        ch.push((ParamId::MicroTone, 0.7));
        ch.push((ParamId::CrackleLevel, 0.9));
        let b = render(&scene(&ch), 0.5);
        assert_eq!(a, b, "micro_tone or crackle_level alone changed the sound");
    }
}

/// Finite, no subnormals, and alive at the sample-rate extremes and at block sizes 1 and
/// 8192 (the same samples: the voice works in chunks).
#[test]
fn textures_are_finite_everywhere() {
    let p = scene(&[
        (ParamId::Micro, 1.0),
        (ParamId::Roughness, 1.0),
        (ParamId::Crackle, 1.0),
        (ParamId::CrackleLevel, 1.0),
        (ParamId::Grit, 1.0),
    ]);
    for fs in [8_000.0, 384_000.0] {
        let x = render_at(fs, &p, 0.3);
        assert!(x
            .iter()
            .all(|v| v.is_finite() && (*v == 0.0 || v.is_normal())));
        assert!(x.iter().any(|&v| v != 0.0));
    }
    let n = 20_000;
    assert_eq!(render_frames(FS, &p, n, 1), render_frames(FS, &p, n, 8192));
}

#[test]
#[ignore = "a report: the cost per sample of the textures (timing, not a check)"]
fn report_cost() {
    let cost = |changes: &[(ParamId, f64)]| {
        let p = scene(changes);
        let mut v = Voice::new(FS, &p);
        let mut out = vec![0f32; 4096];
        let blocks = 200;
        let t = std::time::Instant::now();
        for _ in 0..blocks {
            v.process(&mut out);
        }
        t.elapsed().as_secs_f64() * 1e9 / (blocks * 4096) as f64
    };
    for (name, action) in [("roll", &[][..]), ("rub", &RUB[..])] {
        let mut with = action.to_vec();
        with.push((ParamId::Micro, 0.5));
        with.push((ParamId::Crackle, 0.5));
        let (off, on) = (cost(action), cost(&with));
        println!("{name}: {off:.1} ns/sample off, {on:.1} ns/sample with micro and crackle");
    }
}
