//! Golden hashes: every built-in preset rendered by the `trundle` binary must give the same
//! samples, bit for bit, as when the hashes were recorded.
//!
//! This guards refactorings ("same sounds where nothing was meant to change"): a change
//! that is *meant* to alter a preset's sound re-records the hashes with
//!
//! ```sh
//! TRUNDLE_BLESS=1 cargo test -p trundle-cli --test golden
//! ```
//!
//! and says so in the CHANGELOG (**(sound)**). Each preset is rendered twice, 4 s at
//! 48 kHz as 32-bit float without normalization: once as the object's sound, in stereo (the
//! hash covers both channels, interleaved as in the file; the scene's safety limiter is on
//! unless the preset turns it off), and once as the raw force (`--force-only`, mono), so a
//! change is located on the action or the object side.
//!
//! The modal bank's SIMD kernels differ in the last bits (`trundle_dsp::object::kernels::Kernel`), so
//! the hashes are recorded per kernel: the file holds one section per kernel name, and a
//! machine whose best kernel has no section yet fails with the hashes it computed, to be
//! added with `TRUNDLE_BLESS=1`.

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;
use std::process::Command;
use trundle_dsp::object::kernels::Kernel;
use trundle_dsp::scene::preset::BUILTIN_PRESETS;

use trundle_test_support::cli::bin;
use trundle_test_support::scratch::Scratch;
const GOLDEN: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden_hashes.txt");

/// FNV-1a, 64 bit: enough to tell any change of a sample from none.
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

fn scratch() -> Scratch {
    trundle_test_support::scratch::scratch("renders")
}

/// Hash of the sample data of one render (the WAV's `data` chunk only, so a header change
/// alone — e.g. a new metadata chunk — is not a sound change), which must have `channels`
/// channels.
fn render_hash(dir: &Path, preset: &str, extra: &[&str], channels: u16) -> u64 {
    let out = dir.join(format!("{preset}{}.wav", extra.join("")));
    let o = Command::new(bin())
        .args(["render", "--preset", preset, "--seconds", "4"])
        .args([
            "--sample-rate",
            "48000",
            "--format",
            "f32",
            "--no-normalize",
        ])
        .args(["--force", "-o"])
        .arg(&out)
        .args(extra)
        .output()
        .expect("the trundle binary runs");
    assert!(
        o.status.success(),
        "render {preset} {extra:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let mut r = hound::WavReader::open(&out).unwrap();
    assert_eq!(r.spec().channels, channels, "{preset} {extra:?}");
    assert_eq!(
        r.len(),
        4 * 48_000 * u32::from(channels),
        "{preset} {extra:?}"
    );
    let bytes: Vec<u8> = r
        .samples::<f32>()
        .flat_map(|s| s.unwrap().to_le_bytes())
        .collect();
    fnv1a(&bytes)
}

/// `kernel → (render name → hash)` from the golden file.
fn read_golden() -> BTreeMap<String, BTreeMap<String, String>> {
    let mut all = BTreeMap::new();
    let Ok(text) = fs::read_to_string(GOLDEN) else {
        return all;
    };
    let mut section = String::new();
    for line in text.lines().map(str::trim) {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        if let Some(k) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            section = k.to_string();
            continue;
        }
        let (name, hash) = line.split_once(' ').expect("golden line: NAME HASH");
        all.entry(section.clone())
            .or_insert_with(BTreeMap::new)
            .insert(name.to_string(), hash.trim().to_string());
    }
    all
}

fn write_golden(all: &BTreeMap<String, BTreeMap<String, String>>) {
    let mut text = String::from(
        "# Golden hashes of every built-in preset (crates/trundle-cli/tests/golden.rs).\n\
         # Re-record only for an intended sound change: TRUNDLE_BLESS=1 cargo test -p trundle-cli --test golden\n",
    );
    for (kernel, hashes) in all {
        text.push_str(&format!("\n[{kernel}]\n"));
        for (name, hash) in hashes {
            text.push_str(&format!("{name} {hash}\n"));
        }
    }
    fs::write(GOLDEN, text).unwrap();
}

#[test]
fn every_preset_renders_the_recorded_samples() {
    let dir = scratch();
    let kernel = Kernel::detect().name().to_string();
    let mut now = BTreeMap::new();
    for (stem, _) in BUILTIN_PRESETS {
        for (suffix, extra, channels) in [("", &[][..], 2), (":force", &["--force-only"][..], 1)] {
            let h = render_hash(&dir, stem, extra, channels);
            now.insert(format!("{stem}{suffix}"), format!("{h:016x}"));
        }
    }
    let mut all = read_golden();
    if std::env::var_os("TRUNDLE_BLESS").is_some() {
        all.insert(kernel, now);
        write_golden(&all);
        return;
    }
    let Some(recorded) = all.get(&kernel) else {
        panic!(
            "no golden hashes for the {kernel} kernel in {GOLDEN}; record them with \
             TRUNDLE_BLESS=1 cargo test -p trundle-cli --test golden. Computed: {now:#?}"
        );
    };
    let changed: Vec<String> = now
        .iter()
        .filter(|(name, hash)| recorded.get(*name) != Some(hash))
        .map(|(name, hash)| format!("{name}: {hash} (recorded {:?})", recorded.get(name)))
        .collect();
    let missing: Vec<&String> = recorded.keys().filter(|k| !now.contains_key(*k)).collect();
    assert!(
        changed.is_empty() && missing.is_empty(),
        "presets whose samples changed:\n{}\nno longer rendered: {missing:?}\n\
         (an intended sound change: re-record with TRUNDLE_BLESS=1 and mark it in CHANGELOG.md)",
        changed.join("\n")
    );
    println!(
        "{} renders identical to the golden hashes ({kernel})",
        now.len()
    );
}
