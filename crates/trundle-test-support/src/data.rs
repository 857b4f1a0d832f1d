//! Data from outside the repository. A test that needs it is marked
//! `#[ignore = "needs …"]` (the summary then says "ignored", honestly) and fails, naming
//! what to install, when it is run without it; CI installs the data and runs the ignored
//! tests.

use std::path::{Path, PathBuf};

/// Where Debian's `hydrogen-drumkits` installs its kits.
pub const HYDROGEN_KITS: &str = "/usr/share/hydrogen/data/drumkits";

/// The reason the tests that need [`HYDROGEN_KITS`] give in their `#[ignore]`.
pub const NEEDS_HYDROGEN: &str =
    "needs Debian's hydrogen-drumkits (apt-get install hydrogen-drumkits)";

/// The file `name` of [`HYDROGEN_KITS`] (`ForzeeStereo/AgogoLow-0.wav`); panics saying
/// what to install when it is missing.
pub fn hydrogen_kit_file(name: &str) -> PathBuf {
    let path = Path::new(HYDROGEN_KITS).join(name);
    assert!(
        path.is_file(),
        "{} not found: this test {NEEDS_HYDROGEN}",
        path.display()
    );
    path
}

/// Debian's `fluid-soundfont-gm`: the FluidR3 General MIDI SoundFont.
pub const FLUID_SF2: &str = "/usr/share/sounds/sf2/FluidR3_GM.sf2";

/// The reason the strike-corpus tests give in their `#[ignore]`.
pub const NEEDS_STRIKES: &str = "needs Debian's hydrogen-drumkits and fluid-soundfont-gm (apt-get install hydrogen-drumkits fluid-soundfont-gm)";

/// [`FLUID_SF2`]; panics saying what to install when it is missing.
pub fn fluid_soundfont() -> PathBuf {
    let path = PathBuf::from(FLUID_SF2);
    assert!(
        path.is_file(),
        "{FLUID_SF2} not found: this test {NEEDS_STRIKES}"
    );
    path
}
