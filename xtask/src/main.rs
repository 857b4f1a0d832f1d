//! `cargo xtask bundle trundle --release` → `target/bundled/Trundle.clap` and `.vst3`.
//!
//! A thin wrapper over nice-plug's bundler with one correction. The bundler also copies
//! `target/<profile>/<package>` into `bundled/` as a "standalone" whenever that file
//! exists. For the `trundle` package that file is not the plugin at all: it is the CLI
//! (`trundle-cli`'s binary is named `trundle`, left there by `cargo run --release -p
//! trundle-cli`), while the plugin's standalone binary is `trundle-standalone`. So after
//! bundling, that stray copy is removed again.

use std::path::PathBuf;

/// The names nice-plug gives the standalone copy of package `trundle` (display name from
/// `bundler.toml`) on each platform.
const STRAY_STANDALONES: &[&str] = &["Trundle", "Trundle.exe", "Trundle.app"];

fn main() -> nice_plug_xtask::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    nice_plug_xtask::main_with_args("cargo xtask", args.clone())?;
    let bundles_trundle = args.first().is_some_and(|c| c.starts_with("bundle"))
        && args.iter().skip(1).any(|a| a == "trundle");
    if bundles_trundle {
        // `main_with_args` has made the workspace root the current directory.
        let metadata = cargo_metadata::MetadataCommand::new()
            .manifest_path("./Cargo.toml")
            .no_deps()
            .exec()?;
        let bundled = PathBuf::from(metadata.target_directory.as_std_path()).join("bundled");
        for name in STRAY_STANDALONES {
            let path = bundled.join(name);
            let removed = if path.is_dir() {
                std::fs::remove_dir_all(&path).is_ok()
            } else {
                path.is_file() && std::fs::remove_file(&path).is_ok()
            };
            if removed {
                eprintln!(
                    "Removed '{}': a copy of the `trundle` CLI binary, not a plugin build",
                    path.display()
                );
            }
        }
    }
    Ok(())
}
