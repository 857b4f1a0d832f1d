//! A bounded mutation fuzzer for preset parsing (runs on stable Rust, in CI).
//!
//! Starts from every built-in preset and applies random mutations — byte flips, deletions,
//! insertions of JSON-significant bytes, truncation, duplication of spans, numbers replaced
//! by extreme or non-finite literals, keys renamed, versions bumped — plus pure random byte
//! strings. For every input, parsing must return (never panic), and any preset it accepts
//! must hold a parameter set that is valid for the table (finite, in range, whole where it
//! must be) and round-trip through `to_json`. Each run covers `CASES` inputs from a fixed
//! seed (so a failure reproduces); inputs that ever failed are kept as regression cases in
//! `REGRESSIONS`.
#![cfg(feature = "presets")]

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use trundle_dsp::params::PARAMS;
use trundle_dsp::scene::preset::{Preset, BUILTIN_PRESETS};

const CASES: usize = 60_000;

/// Inputs found by earlier fuzzing runs that once misbehaved (kept forever).
const REGRESSIONS: &[&str] = &[
    // A number that overflows f64 parses as infinity in some JSON readers.
    r#"{"trundle_preset":1,"name":"x","params":{"size":1e999}}"#,
    // Negative zero and exponent forms of integers for an integer parameter.
    r#"{"trundle_preset":1,"name":"x","params":{"modes":-0,"seed":1e3}}"#,
    // Version as a float, as a string, negative, huge.
    r#"{"trundle_preset":1.5,"name":"x"}"#,
    r#"{"trundle_preset":"1","name":"x"}"#,
    r#"{"trundle_preset":-1,"name":"x"}"#,
    r#"{"trundle_preset":18446744073709551616,"name":"x"}"#,
    // Enum by out-of-range index, by fractional index, by name with odd case.
    r#"{"trundle_preset":1,"name":"x","params":{"shape":9}}"#,
    r#"{"trundle_preset":1,"name":"x","params":{"shape":1.5}}"#,
    r#"{"trundle_preset":1,"name":"x","params":{"shape":"PLATE"}}"#,
    // Duplicate keys, deep nesting, a BOM.
    r#"{"trundle_preset":1,"name":"x","params":{"size":0.2,"size":9}}"#,
    "\u{feff}{\"trundle_preset\":1,\"name\":\"x\"}",
];

fn check(input: &str) {
    match Preset::from_json(input) {
        Ok(p) => {
            for (spec, v) in p.params.iter() {
                assert!(
                    spec.validate(v).is_ok(),
                    "accepted invalid {} = {v} from {input:?}",
                    spec.key
                );
            }
            let again = Preset::from_json(&p.to_json()).expect("a written preset reads back");
            assert_eq!(again, p);
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(!msg.is_empty());
        }
    }
}

fn mutate(rng: &mut SmallRng, base: &[u8]) -> Vec<u8> {
    let mut v = base.to_vec();
    let rounds = rng.random_range(1..=4);
    for _ in 0..rounds {
        if v.is_empty() {
            v.push(b'{');
        }
        let i = rng.random_range(0..v.len());
        match rng.random_range(0..9) {
            0 => v[i] ^= 1 << rng.random_range(0..8),
            1 => {
                v.remove(i);
            }
            2 => {
                let alphabet = b"{}[]\",:0123456789-+.eE \ntrufalsn";
                let b = alphabet[rng.random_range(0..alphabet.len())];
                v.insert(i, b);
            }
            3 => v.truncate(i),
            4 => {
                let j = rng.random_range(i..v.len());
                let span = v[i..j].to_vec();
                v.splice(i..i, span);
            }
            5 => {
                // Replace the number starting at or after i by an extreme literal.
                let lits: [&[u8]; 8] = [
                    b"1e308",
                    b"-1e308",
                    b"1e999",
                    b"NaN",
                    b"-0",
                    b"0.0000001",
                    b"1e-320",
                    b"99999999999999999999",
                ];
                if let Some(s) = (i..v.len()).find(|&k| v[k].is_ascii_digit()) {
                    let e = (s..v.len())
                        .find(|&k| !(v[k].is_ascii_digit() || v[k] == b'.'))
                        .unwrap_or(v.len());
                    let lit = lits[rng.random_range(0..lits.len())];
                    v.splice(s..e, lit.iter().copied());
                }
            }
            6 => {
                // Rename a parameter key to another one or to garbage.
                let key = PARAMS[rng.random_range(0..PARAMS.len())].key.as_bytes();
                if let Some(s) = (i..v.len()).find(|&k| v[k] == b'"') {
                    if let Some(e) = (s + 1..v.len()).find(|&k| v[k] == b'"') {
                        v.splice(s + 1..e, key.iter().copied());
                    }
                }
            }
            7 => {
                let s = String::from_utf8_lossy(&v)
                    .replace("\"trundle_preset\": 1", "\"trundle_preset\": 2");
                v = s.into_bytes();
            }
            _ => v.push(rng.random()),
        }
    }
    v
}

#[test]
fn preset_parser_survives_mutations_and_random_bytes() {
    for r in REGRESSIONS {
        check(r);
    }
    let mut rng = SmallRng::seed_from_u64(0x7275_6e64_6c65);
    let mut accepted = 0usize;
    for case in 0..CASES {
        let input: Vec<u8> = if case % 10 == 0 {
            let n = rng.random_range(0..256);
            (0..n).map(|_| rng.random()).collect()
        } else {
            let (_, base) = BUILTIN_PRESETS[case % BUILTIN_PRESETS.len()];
            mutate(&mut rng, base.as_bytes())
        };
        let text = String::from_utf8_lossy(&input);
        if Preset::from_json(&text).is_ok() {
            accepted += 1;
        }
        check(&text);
    }
    println!(
        "preset fuzz: {CASES} inputs + {} regressions, {accepted} accepted as valid presets",
        REGRESSIONS.len()
    );
}
