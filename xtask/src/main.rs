//! `cargo xtask bundle trundle --release` → `target/bundled/Trundle.clap` and `.vst3`.
fn main() -> nice_plug_xtask::Result<()> {
    nice_plug_xtask::main()
}
