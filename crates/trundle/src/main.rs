//! Trundle as a standalone application (feature `standalone`): JACK or ALSA output, the
//! editor in a window. Used for the editor screenshot (`crates/trundle/screenshot.sh`).
use nice_plug::prelude::*;
use trundle::Trundle;

fn main() {
    nice_export_standalone::<Trundle>();
}
