//! Helpers shared by the host tests (`tests/clap_host.rs`, `tests/strict_host.rs`).

use crate::{bundle, clap_param_id, Block, Bundle, Instance, Transport};
use clack_host::prelude::ClapId;

/// The CLAP ID nice-plug gives the parameter with stable key `key`.
pub fn id(key: &str) -> ClapId {
    ClapId::new(clap_param_id(key))
}

/// The built bundle, loaded (built first when missing or stale).
pub fn load_bundle() -> Bundle {
    let path = bundle::ensure_clap_bundle().unwrap_or_else(|e| panic!("no bundle: {e}"));
    Bundle::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// A new instance of the plugin.
pub fn new_instance(b: &Bundle) -> Instance {
    b.instantiate().unwrap_or_else(|e| panic!("{e}"))
}

/// Largest magnitude in `x`.
pub fn peak(x: &[f32]) -> f32 {
    x.iter().fold(0.0f32, |m, v| m.max(v.abs()))
}

/// The CLAP value for a plain value, as the plugin parses typed text.
pub fn plain(inst: &mut Instance, key: &str, v: f64) -> f64 {
    inst.text_value(id(key), &format!("{v}"))
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Root mean square of `x` (0 for an empty slice).
pub fn rms(x: &[f32]) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    (x.iter().map(|v| f64::from(*v) * f64::from(*v)).sum::<f64>() / x.len() as f64).sqrt()
}

/// The first index from which `a` and `b` differ bit for bit, if any.
pub fn first_difference(a: &[f32], b: &[f32]) -> Option<usize> {
    assert_eq!(a.len(), b.len(), "lengths differ");
    a.iter()
        .zip(b)
        .position(|(x, y)| x.to_bits() != y.to_bits())
}

/// Render (panicking on host errors, non-finite, subnormal or unwritten samples on either
/// channel: see [`Instance::render`]) and return the mid, (L + R)/2: what the determinism
/// and level checks compare. While the two channels are equal (width 0, or the core still
/// mono) the mid is the channel itself, bit for bit.
pub fn render(inst: &mut Instance, blocks: &[Block]) -> Vec<f32> {
    let [l, r] = inst.render(blocks).unwrap_or_else(|e| panic!("{e}"));
    l.iter().zip(&r).map(|(a, b)| 0.5 * (a + b)).collect()
}

/// nice-plug's state format: an 8-byte little-endian length, then JSON.
pub fn state_json(state: &[u8]) -> String {
    let len = u64::from_le_bytes(state[..8].try_into().unwrap()) as usize;
    String::from_utf8(state[8..8 + len].to_vec()).expect("JSON state")
}

/// A state in nice-plug's format holding `json`.
pub fn state_bytes(json: &str) -> Vec<u8> {
    let mut out = (json.len() as u64).to_le_bytes().to_vec();
    out.extend_from_slice(json.as_bytes());
    out
}

/// `text` as a JSON string literal.
pub fn json_string(text: &str) -> String {
    let mut out = String::from("\"");
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// The state `json` with a persisted string field `field` holding `text` (as the plugin's
/// `#[persist]` slots store their JSON: the object, the body EQ curve).
pub fn with_state_field(json: &str, field: &str, text: &str) -> String {
    let tag = "\"state_version\":\"1\"";
    assert!(json.contains(tag), "{json}");
    json.replace(tag, &format!("{tag},\"{field}\":{}", json_string(text)))
}

/// One second at 48 kHz in blocks of 512, transport playing, from activation to deactivation.
pub fn one_second(inst: &mut Instance) -> Vec<f32> {
    inst.activate(48_000.0, 512).unwrap();
    let blocks: Vec<Block> = (0..94)
        .map(|_| Block {
            len: 512,
            events: Vec::new(),
            transport: Transport::Playing,
            notes: Vec::new(),
        })
        .collect();
    let out = render(inst, &blocks);
    inst.deactivate().unwrap();
    out
}
