//! `trundle match RECORDING -o preset.json [--seconds S] [--seeds K] [--budget N] [--tries T]
//! [--jobs J] [--strike STRIKE.wav] [--json]`: a preset that sounds like a recording, found
//! by analysis by synthesis (issue #25 item 2; docs/guide/match.md).
//!
//! ```text
//! RECORDING ─► excerpt (the middle S s) ─► profile (compare's four measures, once)
//!   ─► cue: waveform kurtosis → rub / roll / scratch (the search's start on the action disk)
//!   ─► first estimates of the textures off the profile (match_start: strokes, bumps, …)
//!   ─► the noise bar: noise shaped to its spectrum, compared (match_search::noise_bar)
//!   ─► tonal cue (match_pitch: power on one pitch's harmonics, a steady pitch) ─► friction
//!      restarts, each object sized so the mode its contact locks onto sits on the pitch
//!   [--strike ─► fit-object ─► the candidates play the fitted object]
//!   ─► CMA-ES over match_space::SPACE, restarts over (ball material, shape);
//!      each candidate rendered at K seeds, heard through its body EQ, judged (match_search)
//!   [--tries T ─► T such searches at search seeds S … S+T−1 from one shared opening
//!    (screening and sweeps: match_opening::open), the lowest search loss kept]
//!   ─► the best, through its curve, at 3 OTHER seeds: each measure's value and verdict,
//!      closer than the noise or not
//!   ─► preset (params, seed, body EQ curve, "match" record) ─► exit 0 (a match) or 3
//! ```
//!
//! Exit codes: 0 the preset is a match (all four measures within their limits at every
//! validation seed); 3 the preset is the best found but outside the limits (written, and
//! the failing measures named with their numbers); 2 bad input; 1 I/O failure.

use crate::compare_cmd::{self, load_mono};
use crate::error::{failure, input, quote, CliError};
use crate::fit_cmd::{fit_file, write_text};
use crate::match_edges::read_fades;
use crate::match_opening::open;
use crate::match_pitch::{friction_starts, harmonic_presearch, tone, tune_size, with_turning};
use crate::match_search::{
    judge, noise_bar, own_spectrum_goal, refine_winner, search_from, Judged, Plan, Target,
    BRIGHTNESS_GOAL, BRIGHTNESS_WEIGHT, MIN_BRIGHTNESS, PRESET_PRE_ROLL_S,
};
use crate::match_space::{action_cue, action_name, dims, restarts_for, with_restart, RESTARTS};
use crate::match_start::{estimate, starts, stroke_period};
use crate::output::check_destination;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde_json::{json, Value};
use std::path::PathBuf;
use std::time::Instant;
use trundle_dsp::analysis::compare::{profile, Comparison, Verdict, TOP_HZ};
use trundle_dsp::object::fitted::{LoadedObject, ObjectFile};
use trundle_dsp::scene::preset::{take_to_json, Preset};
use trundle_dsp::scene::take::Take;
use trundle_dsp::{ParamId, Params};

/// Exit code of a match outside the limits (the best preset is still written).
pub const EXIT_OUTSIDE: u8 = 3;
/// Seeds the winner is validated at: none of them is a search seed (those are 1 … K).
pub const VALIDATION_SEEDS: [u32; 3] = [1001, 2002, 3003];
/// A restart stops when its loss at the search seeds is this far inside the limits (a
/// loss of 1 is the worst measure at its limit): a margin for the unseen seeds. 0.6
/// (28 Nov 2026) gave the tyres, traffic and the grinding stone (the clips nearest it)
/// the same presets to the bit: the tyres' search reaches 0.58, under either target, and
/// traffic's (0.76) and the grinding stone's (0.90) never reach 0.75.
pub const TARGET_LOSS: f64 = 0.75;
/// [`TARGET_LOSS`] of a tonal recording: a sung tone's modulation distance moves by up to
/// ~1 dB from one stretch of its song to another (`match_search::friction_lead_s`), so a
/// friction match needs a wider margin at the stretches searched to hold at the unseen ones.
pub const TONAL_TARGET_LOSS: f64 = 0.6;

/// Most independent searches `--tries` runs.
pub const MAX_TRIES: u32 = 16;

/// Arguments of `trundle match`.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Examples:
  trundle match gravel.wav -o gravel.json
  trundle match gravel.wav -o gravel.json --budget 600 --jobs 0
  trundle match rub.wav -o rub.json --strike knock.wav --json
Exit codes: 0 a match (every measure within its limit at 3 unseen seeds), 3 the best
preset found is written but outside the limits (the failing measures are named),
2 bad input, 1 I/O failure.")]
pub struct MatchArgs {
    /// The recording to match (WAV, FLAC or OGG; mono mix).
    pub recording: PathBuf,
    /// The preset file to write (JSON).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Seconds of the recording matched (its middle; the whole if shorter).
    #[arg(long, default_value_t = 5.0)]
    pub seconds: f64,
    /// Seeds every candidate is rendered at (its loss is ½(mean + max) over them).
    #[arg(long, default_value_t = 2)]
    pub seeds: u32,
    /// Candidates judged in all (each rendered at every seed; the six best judged again at
    /// two more seeds count twice).
    #[arg(long, default_value_t = 256)]
    pub budget: usize,
    /// Threads (0: every core).
    #[arg(long, default_value_t = 1)]
    pub jobs: usize,
    /// A recorded strike of the object: fit-object runs on it and the candidates play it.
    #[arg(long, value_name = "STRIKE.wav")]
    pub strike: Option<PathBuf>,
    /// The search's random draws.
    #[arg(long, default_value_t = 1)]
    pub search_seed: u64,
    /// Independent searches (search seeds S, S + 1, …, each with the whole budget), the one
    /// with the lowest loss at the search seeds kept. Their opening (screening and sweeps,
    /// no search seed heard) runs once: 3 tries cost about 2–2.3× one. A search's
    /// winner depends on its path as much as on the recording (docs/guide/match.md, "A
    /// match is a draw"); more tries take the best of more draws.
    #[arg(long, default_value_t = 1)]
    pub tries: u32,
    /// Overwrite an existing file.
    #[arg(long)]
    pub force: bool,
    /// Print the report as JSON (no progress bar).
    #[arg(long)]
    pub json: bool,
}

fn verdict_json(v: &Verdict) -> Value {
    json!({ "value": v.value, "limit": v.limit, "passed": v.passed })
}

fn comparison_json(seed: u32, c: &Comparison) -> Value {
    json!({
        "seed": seed,
        "loss": c.loss(),
        "passed": c.passed(),
        "measures_passed": c.measures_passed(),
        "spectrum_db": verdict_json(&c.spectrum),
        "modulation_db": verdict_json(&c.modulation),
        "texture": verdict_json(&c.texture),
        "kurtosis_ratio": verdict_json(&c.kurtosis),
        "crest_db": verdict_json(&c.crest),
    })
}

/// The failing measures of a comparison, each with its number and limit.
pub fn failing(c: &Comparison) -> Vec<String> {
    let mut out = Vec::new();
    if !c.spectrum.passed {
        out.push(format!(
            "spectrum {:.2} dB (limit {:.1})",
            c.spectrum.value, c.spectrum.limit
        ));
    }
    // Modulation and texture name where they are furthest off (`compare`'s closing lines).
    if !c.modulation.passed {
        let at = c.furthest_modulation().map_or_else(String::new, |m| {
            format!("; furthest {}", compare_cmd::modulation_gap_text(&m))
        });
        out.push(format!(
            "modulation {:.2} dB (limit {:.1}{at})",
            c.modulation.value, c.modulation.limit
        ));
    }
    if !c.texture.passed {
        let at = c.furthest_texture().map_or_else(String::new, |t| {
            format!("; furthest the {}", compare_cmd::texture_gap_text(&t))
        });
        out.push(format!(
            "texture {:.2} (limit {:.1}{at})",
            c.texture.value, c.texture.limit
        ));
    }
    if !c.kurtosis.passed {
        out.push(format!(
            "kurtosis ×{:.2} (limit ×/÷{:.0})",
            c.kurtosis.value, c.kurtosis.limit
        ));
    }
    if !c.crest.passed {
        out.push(format!(
            "crest {:+.1} dB (limit ±{:.0})",
            c.crest.value, c.crest.limit
        ));
    }
    out
}

/// Run `trundle match`: the report and the exit code (0 or [`EXIT_OUTSIDE`]).
pub fn run(args: &MatchArgs) -> Result<(String, u8), CliError> {
    let started = Instant::now();
    check_destination(&args.output, "--output", args.force)?;
    if !(args.seconds.is_finite() && args.seconds >= 1.0) {
        return Err(input(format!(
            "--seconds must be at least 1 (s), got {}",
            args.seconds
        )));
    }
    if !(1..=8).contains(&args.seeds) {
        return Err(input(format!("--seeds must be 1 … 8, got {}", args.seeds)));
    }
    if !(1..=MAX_TRIES).contains(&args.tries) {
        return Err(input(format!(
            "--tries must be 1 … {MAX_TRIES}, got {}",
            args.tries
        )));
    }
    if args.budget < 8 {
        return Err(input(format!(
            "--budget must be at least 8 candidates, got {}",
            args.budget
        )));
    }
    let (x, fs) = load_mono(&args.recording)?;
    let shown = quote(&args.recording.display().to_string());
    let want = (args.seconds * fs) as usize;
    // The recording's fades, read off the whole of it (the preset plays them); the
    // candidates hear them only when the excerpt is the whole recording.
    let fades = read_fades(&x, fs);
    let whole = x.len() <= want;
    let excerpt = if x.len() > want {
        let a = (x.len() - want) / 2;
        x[a..a + want].to_vec()
    } else {
        x
    };
    let top = TOP_HZ.min(0.5 * fs);
    let reference =
        profile(&excerpt, fs, top, "recording").map_err(|e| input(format!("{shown}: {e}")))?;
    let object = match &args.strike {
        None => None,
        Some(path) => {
            let (fit, _, _) = fit_file(path)?;
            let source = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let file = ObjectFile {
                object: fit,
                source,
            };
            let loaded = LoadedObject::new(file.clone()).map_err(|e| {
                input(format!(
                    "{}: the fitted object is not playable: {e}",
                    quote(&path.display().to_string())
                ))
            })?;
            Some((file, std::sync::Arc::new(loaded)))
        }
    };
    let tone = tone(&excerpt, fs);
    let tonal = tone.filter(|t| t.is_tonal());
    // The baseline the report holds the match to: noise with the recording's spectrum.
    let noise = noise_bar(&reference, &excerpt, fs);
    let target = Target {
        tonal: tonal.is_some(),
        reference,
        sample_rate_hz: fs,
        samples: excerpt.len(),
        object: object.as_ref().map(|o| o.1.clone()),
        take: fades.filter(|_| whole),
    };
    // The start: the defaults (the limiter on, as a render plays it), the velocity inside
    // the searched range; every restart's start (each action corner, other balls and
    // shapes) judged first, the search run from the best.
    let estimate = estimate(&target.reference, stroke_period(&excerpt, fs));
    // Sound lifted off for a share of the time is that much more kurtotic: the lift's, not
    // the contact's impulsiveness.
    let cue = action_cue(target.reference.kurtosis * (1.0 - estimate.stroke_lift.unwrap_or(0.0)));
    let mut start = Params::default();
    start.set_clamped(ParamId::Velocity, 0.4);
    let dims = dims();
    let threads = if args.jobs == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        args.jobs
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| failure(format!("cannot start {threads} threads: {e}")))?;
    let bar = if args.json {
        ProgressBar::hidden()
    } else {
        let style = ProgressStyle::with_template(
            "matching [{bar:40}] {pos}/{len} candidates  {elapsed} elapsed, eta {eta}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> ");
        ProgressBar::with_draw_target(
            Some(args.budget as u64 * u64::from(args.tries)),
            ProgressDrawTarget::stderr(),
        )
        .with_style(style)
    };
    let restarts: Vec<Params> = restarts_for(cue, RESTARTS.len())
        .iter()
        .map(|r| with_restart(&start, r))
        .collect();
    // A tonal recording: friction restarts tuned to its pitch, screened first.
    // Each moved first to the grid point whose own spectrum is closest (the harmonics'
    // balance), on the pool.
    let mut all_starts = tonal.map_or_else(Vec::new, |t| {
        pool.install(|| {
            friction_starts(t.pitch_hz, fs)
                .iter()
                .flat_map(|p| {
                    with_turning(
                        harmonic_presearch(p, &target.reference.spectrum, t.pitch_hz, fs, top),
                        t.pitch_hz,
                        fs,
                    )
                })
                .collect()
        })
    });
    let friction_restarts = all_starts.len();
    all_starts.extend(starts(&restarts, &estimate));
    let mut plan = Plan {
        dims: &dims,
        start,
        starts: all_starts,
        textures: (!estimate.is_empty()).then(|| estimate.clone()),
        seeds: (1..=args.seeds).collect(),
        budget: args.budget,
        seed: args.search_seed,
        target_loss: if target.tonal {
            TONAL_TARGET_LOSS
        } else {
            TARGET_LOSS
        },
    };
    // Each try: the search, then a friction winner sized again so the mode it locks onto
    // (at its searched pressure, speed and position) sings on the recording's pitch and
    // judged again for its curve, then its body EQ refined on what the one-pass curve
    // leaves (`refine_winner`). The lowest loss at the search seeds is kept (the first on a
    // tie); the validation seeds are never heard before the winner is chosen.
    // The opening (screening, sweeps, the textures' retry) hears no search seed: it runs
    // once, and every try's CMA-ES starts from a copy of it.
    let opening = open(&target, &plan, &pool, &bar);
    let opened = opening.evaluations;
    // The bar's length once the opening's cost is known: each try judges up to the rest.
    bar.set_length((opened + args.tries as usize * args.budget.saturating_sub(opened)) as u64);
    let mut evaluations = opened;
    let mut try_losses = Vec::with_capacity(args.tries as usize);
    let mut chosen: Option<(Judged, u64)> = None;
    for k in 0..u64::from(args.tries) {
        plan.seed = args.search_seed.wrapping_add(k);
        let found = search_from(&target, &plan, &opening, &pool, &bar);
        evaluations += found.evaluations - opened;
        let mut best = found.best;
        if let Some(t) = tonal.filter(|_| best.params.get(ParamId::Friction) > 0.0) {
            if let Some(p) = tune_size(&best.params, t.pitch_hz, fs) {
                if p != best.params {
                    best = judge(&target, &p, &plan.seeds, None);
                }
            }
        }
        let best = refine_winner(&target, &best, &plan.seeds);
        try_losses.push(best.loss);
        if chosen.as_ref().is_none_or(|(c, _)| best.loss < c.loss) {
            chosen = Some((best, plan.seed));
        }
    }
    bar.finish_and_clear();
    let (best, chosen_seed) = chosen.expect("at least one try");
    // Validation: the winner through its own curve at seeds the search never heard.
    let validation: Judged = judge(&target, &best.params, &VALIDATION_SEEDS, Some(&best.curve));
    let matched = validation.comparisons.len() == VALIDATION_SEEDS.len()
        && validation.comparisons.iter().all(Comparison::passed);
    let brightness = validation.brightness;
    let seconds = started.elapsed().as_secs_f64();
    let name = args
        .recording
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let (ax, ay) = (
        best.params.get(ParamId::ActionX),
        best.params.get(ParamId::ActionY),
    );
    let action = action_name(ax, ay);
    let per_seed: Vec<Value> = VALIDATION_SEEDS
        .iter()
        .zip(&validation.comparisons)
        .map(|(&s, c)| comparison_json(s, c))
        .collect();
    let (own_goal_db, own_weight) = own_spectrum_goal(&target);
    let loss_note = format!(
        "½(mean + max) of compare's loss over the validation seeds, + {BRIGHTNESS_WEIGHT} per unit of brightness ratio (the mean over the seeds) under {BRIGHTNESS_GOAL}, + {own_weight} per dB of the model's own spectrum beyond {own_goal_db} dB{}",
        if target.tonal { " (a tonal recording)" } else { "" }
    );
    // Closer than spectrum-shaped noise (issue #25): the worst validation seed under the
    // noise's modulation and texture distances.
    let worst =
        |f: fn(&Comparison) -> f64| validation.comparisons.iter().map(f).fold(0.0, f64::max);
    let (worst_modulation, worst_texture) =
        (worst(|c| c.modulation.value), worst(|c| c.texture.value));
    let beats_noise =
        noise.map(|n| worst_modulation < n.modulation_db && worst_texture < n.texture);
    // The preset takes the scene as the search heard it: a friction winner after a lead-in
    // (its candidates were judged after one), and with the recording's fades.
    let take = preset_take(fades, &best.params);
    let record = json!({
        "recording": name,
        "seconds": target.samples as f64 / fs,
        "passed": matched,
        "loss": validation.loss,
        "loss_note": loss_note,
        "search_loss": best.loss,
        "search_seeds": plan.seeds,
        "search_seed": chosen_seed,
        "tries": try_losses,
        "validation": per_seed,
        "action": action,
        "start_estimate": estimate.describe(),
        "take": take.as_ref().map(take_to_json),
        "tone": tone.map(|t| json!({
            "pitch_hz": t.pitch_hz,
            "harmonic_share": t.harmonic_share,
            "spread": t.spread,
            "tonal": t.is_tonal(),
        })),
        "friction_restarts": friction_restarts,
        "friction": best.params.get(ParamId::Friction),
        "brightness_at_1_5x_velocity": brightness,
        "own_spectrum_db": validation.own_spectrum_db,
        "shaped_noise": noise.map(|n| json!({
            "modulation_db": n.modulation_db,
            "texture": n.texture,
            "closer": beats_noise,
        })),
        "candidates": evaluations,
        "opening_candidates": opened,
        "elapsed_s": seconds,
        "body_eq": { "bands_hz": best.curve.bands_hz, "gain_db": best.curve.gain_db },
    });
    let mut params = best.params;
    params.set_clamped(ParamId::Seed, f64::from(plan.seeds[0]));
    // The preset plays its body EQ whole (0 = the model's own spectrum).
    params.set_clamped(ParamId::BodyEq, 1.0);
    let preset = Preset {
        name: format!("Matched to {name}"),
        description: format!(
            "trundle match of {name}: {action}, loss {:.2} at seeds {:?} ({})",
            validation.loss,
            VALIDATION_SEEDS,
            if matched {
                "within every limit"
            } else {
                "outside the limits"
            }
        ),
        params,
        automation: Vec::new(),
        balls: Vec::new(),
        object: object.map(|o| o.0),
        body_eq: best.curve.body_eq(),
        take,
        matched: Some(record.clone()),
    };
    write_text(&args.output, &(preset.to_json() + "\n"), args.force)?;
    let code = if matched { 0 } else { EXIT_OUTSIDE };
    if args.json {
        let mut r = record;
        r["output"] = Value::String(args.output.display().to_string());
        r["exit_code"] = Value::from(code);
        return Ok((
            serde_json::to_string_pretty(&r).expect("JSON values serialize") + "\n",
            code,
        ));
    }
    let mut s = format!(
        "{}: {action} (action {ax:.2}, {ay:.2}), {} candidates × {} seeds in {seconds:.1} s; cue {cue} (kurtosis {:.2})\n",
        args.output.display(),
        evaluations,
        plan.seeds.len(),
        target.reference.kurtosis
    );
    s += &format!("start: {}\n", estimate.describe());
    if let Some(t) = take.filter(|t| t.pre_roll_s > 0.0) {
        s += &format!(
            "pre-roll: the preset's renders start {:.2} s into the rub, where its candidates were heard (a stick-slip contact takes ~0.75 s to lock)\n",
            t.pre_roll_s
        );
    }
    if let Some(t) = &fades {
        let heard = if whole {
            "every candidate and the preset's renders play them"
        } else {
            "the preset's renders play them (the candidates, the recording's middle, do not)"
        };
        s += &format!(
            "edges: the recording fades in over {:.2} s and out over {:.2} s; {heard}\n",
            t.fade_in_s, t.fade_out_s
        );
    }
    if args.tries > 1 {
        let losses: Vec<String> = try_losses.iter().map(|l| format!("{l:.2}")).collect();
        s += &format!(
            "tries: {} searches from one opening of {opened} candidates, losses at the search seeds {}; search seed {chosen_seed} kept\n",
            args.tries,
            losses.join(", ")
        );
    }
    match tone {
        Some(t) if t.is_tonal() => {
            s += &format!(
                "tonal: {:.1} Hz ({:.0} % of the power on its harmonics): {friction_restarts} friction restarts; friction {:.2} chosen\n",
                t.pitch_hz,
                100.0 * t.harmonic_share,
                best.params.get(ParamId::Friction)
            );
        }
        _ => s += "not tonal: no friction restarts\n",
    }
    s += &format!(
        "validated at seeds {VALIDATION_SEEDS:?} (not searched): loss {:.2} (search {:.2})\n",
        validation.loss, best.loss
    );
    for (seed, c) in VALIDATION_SEEDS.iter().zip(&validation.comparisons) {
        s += &format!(
            "  seed {seed}: spectrum {:.2} dB, modulation {:.2} dB, texture {:.2}, kurtosis ×{:.2}, crest {:+.1} dB: {} of 4\n",
            c.spectrum.value,
            c.modulation.value,
            c.texture.value,
            c.kurtosis.value,
            c.crest.value,
            c.measures_passed()
        );
    }
    s += &format!(
        "1.5× velocity: spectral centroid ×{:.2}{}; the model's own spectrum (body_eq 0): {:.1} dB from the recording's\n",
        brightness.unwrap_or(f64::NAN),
        if brightness.is_some_and(|b| b < MIN_BRIGHTNESS) {
            format!(" (under ×{MIN_BRIGHTNESS}: not brighter when faster)")
        } else {
            String::new()
        },
        validation.own_spectrum_db
    );
    if let Some(n) = noise {
        s += &format!(
            "against spectrum-shaped noise: modulation {worst_modulation:.2} dB (noise {:.2}), texture {worst_texture:.2} (noise {:.2}) at the worst seed: {}\n",
            n.modulation_db,
            n.texture,
            if beats_noise == Some(true) {
                "closer on both"
            } else {
                "NOT closer on both (the texture is no nearer than the spectrum's)"
            }
        );
    }
    if matched {
        s += "a match: every measure within its limit at every validation seed\n";
    } else {
        s += "NOT a match: no setting found comes within the limits; the best is written.\n";
        for (seed, c) in VALIDATION_SEEDS.iter().zip(&validation.comparisons) {
            let f = failing(c);
            if !f.is_empty() {
                s += &format!("  seed {seed} fails: {}\n", f.join("; "));
            }
        }
    }
    Ok((s, code))
}

/// The take a matched preset plays: the recording's `fades` (read off the whole recording),
/// and for a friction winner a pre-roll of [`PRESET_PRE_ROLL_S`], the lead-in its
/// candidates were heard after ([`crate::match_search::friction_lead_s`]): rendered from the
/// first touch, the sung glass of the corpus was 30 dB quiet for its first 0.2 s where the
/// recording sings (its modulation 3.57 → 3.29 dB and texture 1.65 → 1.31 at its worst
/// unseen seed with a 0.75 s pre-roll). `None` when there is neither.
fn preset_take(fades: Option<Take>, params: &Params) -> Option<Take> {
    let pre_roll_s = if params.get(ParamId::Friction) > 0.0 {
        PRESET_PRE_ROLL_S
    } else {
        0.0
    };
    let fades = fades.unwrap_or_default();
    Take::new(pre_roll_s, fades.fade_in_s, fades.fade_out_s)
        .ok()
        .filter(|t| !t.is_none())
}
