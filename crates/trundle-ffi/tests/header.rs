//! The committed header `include/trundle.h` is what cbindgen makes of the crate today: the
//! test regenerates it (cbindgen as a library, `cbindgen.toml`, plus one
//! `TRUNDLE_PARAM_<KEY>` constant per row of the parameter table) and fails on any
//! difference, so CI catches an ABI change whose header was not regenerated.
//! `TRUNDLE_BLESS=1 cargo test -p trundle-ffi --test header` rewrites it.

use std::fmt::Write as _;
use std::path::Path;
use trundle_dsp::params::{ParamKind, PARAMS};

/// One `#define` per control: its stable ID (its row), with its name, range and choices.
fn param_ids() -> String {
    let mut s = String::from(
        "\n/*\n * Stable IDs of the controls, for the *_set_param functions: each control's row in\n \
         * Trundle's parameter table (rows are only ever appended, so an ID keeps its meaning).\n \
         * Values are in the control's units; a choice's value is its variant's index.\n */\n",
    );
    for (i, p) in PARAMS.iter().enumerate() {
        let macro_name = format!("TRUNDLE_PARAM_{}", p.key.to_uppercase());
        let unit = if p.unit.is_empty() {
            String::new()
        } else {
            format!(" {}", p.unit)
        };
        let what = match p.kind {
            ParamKind::Enum(names) => format!(
                "{}: {}",
                p.name,
                names
                    .iter()
                    .enumerate()
                    .map(|(i, n)| format!("{i} {n}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            _ => format!("{}, {} to {}{unit}", p.name, p.min, p.max),
        };
        writeln!(s, "#define {macro_name} {i} /* {what} */").unwrap();
    }
    s
}

fn generate() -> String {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut config =
        cbindgen::Config::from_file(crate_dir.join("cbindgen.toml")).expect("cbindgen.toml parses");
    // The IDs go inside the include guard, after the declarations.
    config.trailer = Some(param_ids());
    let bindings = cbindgen::Builder::new()
        .with_config(config)
        .with_src(crate_dir.join("src/lib.rs"))
        .generate()
        .expect("cbindgen parses the crate");
    let mut out = Vec::new();
    bindings.write(&mut out);
    String::from_utf8(out).expect("the header is UTF-8")
}

#[test]
fn committed_header_is_current() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../include/trundle.h");
    let fresh = generate();
    if std::env::var_os("TRUNDLE_BLESS").is_some() {
        std::fs::write(&path, &fresh).expect("include/trundle.h is writable");
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    if committed != fresh {
        let line = committed
            .lines()
            .zip(fresh.lines())
            .position(|(a, b)| a != b)
            .map_or(committed.lines().count().min(fresh.lines().count()), |i| i);
        panic!(
            "include/trundle.h is not what cbindgen generates from the crate (first difference \
             at line {}); regenerate it with `TRUNDLE_BLESS=1 cargo test -p trundle-ffi --test \
             header` and commit it",
            line + 1
        );
    }
}

#[test]
fn every_control_has_an_id_in_the_header() {
    let header = generate();
    for (i, p) in PARAMS.iter().enumerate() {
        let line = format!("#define TRUNDLE_PARAM_{} {i} ", p.key.to_uppercase());
        assert!(header.contains(&line), "missing: {line}");
    }
    for f in [
        "trundle_voice_create",
        "trundle_voice_render",
        "trundle_voice_render_interleaved",
        "trundle_last_error",
        "trundle_version",
        "TRUNDLE_STATUS_OK",
    ] {
        assert!(header.contains(f), "{f} is not in the header");
    }
}
