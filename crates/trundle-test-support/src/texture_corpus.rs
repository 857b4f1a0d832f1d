//! The texture corpus of issue #25: real rolling, rubbing and scraping recordings (and bowed
//! strings, the pitched rub of stick-slip friction) out of Debian packages, each a stretch
//! steady enough to be one texture, and the baseline the issue compares a match against:
//! Gaussian noise shaped to the clip's long-term spectrum ([`shaped_noise`]).
//!
//! A clip is a file of a game's data (WAV or OGG Vorbis, decoded by `trundle-io`, the
//! command's own reader; stereo as its mono mix) or a sample of the GM SoundFont (its data
//! only, never looped; of a stereo pair the left sample), trimmed to `start_s … end_s` where
//! the file fades in or out. Every clip passes the four measures of
//! `trundle_dsp::analysis::compare` against its own other half; which clips were tried and
//! left out, and why, is in `docs/corpus.md`.

use crate::soundfont::read_sample;
use std::path::Path;
/// The shaped-noise baseline lives with the judge (`trundle_dsp::analysis::compare::noise`).
pub use trundle_dsp::analysis::compare::noise::{shaped_noise, SHAPE_FRAME};

/// What makes the sound.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Rolling: wheels, tyres.
    Roll,
    /// Rubbing: a surface slid or ground over another, no tool edge.
    Rub,
    /// Scraping: an edge or teeth dragged over a surface (saws, a blade on a grindstone).
    Scrape,
    /// A pitched rub: stick-slip friction locked to a resonance (a bowed string).
    PitchedRub,
}

impl Kind {
    /// The table's word.
    pub fn label(self) -> &'static str {
        match self {
            Kind::Roll => "roll",
            Kind::Rub => "rub",
            Kind::Scrape => "scrape",
            Kind::PitchedRub => "pitched rub",
        }
    }
}

/// Where a clip is read from.
#[derive(Clone, Copy, Debug)]
pub enum Source {
    /// A file (WAV, OGG Vorbis) at this absolute path, installed by the clip's package.
    File(&'static str),
    /// A sample of the FluidR3 GM SoundFont ([`crate::data::FLUID_SF2`]), by its name.
    SoundFont(&'static str),
}

/// One clip of the corpus.
#[derive(Clone, Copy, Debug)]
pub struct Clip {
    /// Short name for the tables.
    pub name: &'static str,
    /// The Debian package that installs it.
    pub package: &'static str,
    /// Where it is read from.
    pub source: Source,
    /// Start of the stretch used (s).
    pub start_s: f64,
    /// End of the stretch used (s; `None`: the end of the file).
    pub end_s: Option<f64>,
    /// What makes the sound.
    pub kind: Kind,
    /// What it is.
    pub what: &'static str,
    /// Licence (the package's `/usr/share/doc/PKG/copyright`).
    pub licence: &'static str,
    /// Copyright holder (the same file).
    pub copyright: &'static str,
}

const TORCS: &str =
    "2000–2005 Eric Espié, Christophe Guionneau, Bernhard Wymann, Andrea Alfieri (TORCS)";
const WIDELANDS: &str = "2002–2019 the Widelands Development Team";
const LINCITY: &str = "1995–2008 I J Peters, Greg Sharp, Corey Keasling and the LinCity-NG authors";
const FLUID: &str = "2000–2002, 2008 Frank Wen; 2008 Toby Smithe (FluidR3 GM)";
const OLPC: &str = "Nils Van Ottorloo, for the OLPC sound samples library";

#[allow(clippy::too_many_arguments)]
const fn clip(
    name: &'static str,
    package: &'static str,
    source: Source,
    start_s: f64,
    end_s: Option<f64>,
    kind: Kind,
    what: &'static str,
    licence: &'static str,
    copyright: &'static str,
) -> Clip {
    Clip {
        name,
        package,
        source,
        start_s,
        end_s,
        kind,
        what,
        licence,
        copyright,
    }
}

/// The corpus (`docs/corpus.md` lists the clips tried and left out).
pub const CORPUS: [Clip; 13] = [
    clip(
        "tyres on asphalt",
        "torcs-data",
        Source::File("/usr/share/games/torcs/data/sound/road-ride.wav"),
        0.75,
        None,
        Kind::Roll,
        "a car's tyres rolling on a road (TORCS road-ride.wav), its fade-in cut",
        "GPL-2+",
        TORCS,
    ),
    clip(
        "metal scraping asphalt",
        "torcs-data",
        Source::File("/usr/share/games/torcs/data/sound/skid_metal.wav"),
        0.0,
        None,
        Kind::Scrape,
        "a car's body scraping along the track (TORCS skid_metal.wav)",
        "GPL-2+",
        TORCS,
    ),
    clip(
        "hand saw",
        "widelands-data",
        Source::File("/usr/share/games/widelands/data/sound/atlanteans/saw/sawing_00.ogg"),
        0.0,
        None,
        Kind::Scrape,
        "a hand saw cutting wood, stroke after stroke (Widelands sawing_00.ogg)",
        "GPL-2+",
        WIDELANDS,
    ),
    clip(
        "sawmill",
        "widelands-data",
        Source::File("/usr/share/games/widelands/data/sound/sawmill/sawmill_00.ogg"),
        0.0,
        None,
        Kind::Scrape,
        "a sawmill's saw in wood (Widelands sawmill_00.ogg)",
        "GPL-2+",
        WIDELANDS,
    ),
    clip(
        "sawmill, steady",
        "widelands-data",
        Source::File("/usr/share/games/widelands/data/sound/sawmill/sawmill_01.ogg"),
        0.0,
        None,
        Kind::Scrape,
        "a sawmill's saw in wood, a steadier take (Widelands sawmill_01.ogg)",
        "GPL-2+",
        WIDELANDS,
    ),
    clip(
        "grinding stone",
        "widelands-data",
        Source::File("/usr/share/games/widelands/data/sound/barbarians/stonegrind.ogg"),
        0.25,
        Some(4.5),
        Kind::Rub,
        "stone ground on stone (Widelands stonegrind.ogg), fade-in and fade-out cut",
        "GPL-2+",
        WIDELANDS,
    ),
    clip(
        "blade on a grindstone",
        "widelands-data",
        Source::File("/usr/share/games/widelands/data/sound/smiths/sharpening.ogg"),
        0.0,
        Some(9.3),
        Kind::Scrape,
        "a blade sharpened on a turning grindstone (Widelands sharpening.ogg), the silent tail cut",
        "GPL-2+",
        WIDELANDS,
    ),
    clip(
        "cart on a dirt track",
        "lincity-ng-data",
        Source::File("/usr/share/games/lincity-ng/sounds/DirtTrack3.wav"),
        0.0,
        None,
        Kind::Roll,
        "wheels on a dirt track (LinCity-NG DirtTrack3.wav, 11 kHz)",
        "GPL-2+ (sound effects dual-licensed CC BY-SA 2.0)",
        LINCITY,
    ),
    clip(
        "traffic",
        "lincity-ng-data",
        Source::File("/usr/share/games/lincity-ng/sounds/TraficHigh2.wav"),
        0.0,
        None,
        Kind::Roll,
        "road traffic, tyres on a street (LinCity-NG TraficHigh2.wav, 11 kHz)",
        "GPL-2+ (sound effects dual-licensed CC BY-SA 2.0)",
        LINCITY,
    ),
    clip(
        "bowed cello",
        "fluid-soundfont-gm",
        Source::SoundFont("Cello C#3(L)"),
        0.2,
        None,
        Kind::PitchedRub,
        "a cello's C#3 bowed (stick-slip friction on a string), the attack cut",
        "MIT",
        FLUID,
    ),
    clip(
        "bowed viola",
        "fluid-soundfont-gm",
        Source::SoundFont("Viola G2(L)"),
        0.2,
        None,
        Kind::PitchedRub,
        "a viola's G2 bowed, the attack cut",
        "MIT",
        FLUID,
    ),
    clip(
        "bowed cello, high",
        "fluid-soundfont-gm",
        Source::SoundFont("Cello C#5(L)"),
        0.2,
        None,
        Kind::PitchedRub,
        "a cello's C#5 bowed, the attack cut",
        "MIT",
        FLUID,
    ),
    clip(
        "finger round a glass rim",
        "cube2-data",
        Source::File(
            "/usr/share/games/cube2/packages/sounds/olpc/NilsVanOttorloo/Musical_Glasses8.wav",
        ),
        0.0,
        Some(2.5),
        Kind::PitchedRub,
        "a musical glass sung by a wet finger circling its rim, 735 Hz with its octave (OLPC \
         sound samples, shipped with Cube 2: Sauerbraten), its last 0.7 s of free ring-down \
         cut",
        "CC-BY-3.0",
        OLPC,
    ),
];

/// A clip's samples: mono, full scale ±1.
#[derive(Clone, Debug)]
pub struct Texture {
    /// The samples of the stretch used.
    pub samples: Vec<f32>,
    /// Sample rate (Hz).
    pub sample_rate_hz: u32,
}

impl Texture {
    /// The samples as `f64` (what the measures read).
    pub fn to_f64(&self) -> Vec<f64> {
        self.samples.iter().map(|&v| f64::from(v)).collect()
    }

    /// The first and the second half (equally long).
    pub fn halves(&self) -> (Vec<f64>, Vec<f64>) {
        let x = self.to_f64();
        let n = x.len() / 2;
        (x[..n].to_vec(), x[n..2 * n].to_vec())
    }

    /// Length (s).
    pub fn seconds(&self) -> f64 {
        self.samples.len() as f64 / f64::from(self.sample_rate_hz)
    }
}

/// The `#[ignore]` reason of the tests that read the corpus.
pub const NEEDS_TEXTURES: &str = "needs Debian's torcs-data, widelands-data, lincity-ng-data, fluid-soundfont-gm and cube2-data (apt-get install torcs-data widelands-data lincity-ng-data fluid-soundfont-gm cube2-data)";

/// Why a clip cannot be read: its message names the package to install.
#[derive(Clone, Debug, PartialEq)]
pub struct CorpusError {
    /// The clip's name.
    pub clip: &'static str,
    /// What went wrong.
    pub problem: String,
}

impl core::fmt::Display for CorpusError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "texture clip {:?}: {}", self.clip, self.problem)
    }
}

impl std::error::Error for CorpusError {}

/// The clip's samples (mono, the stretch `start_s … end_s`); an error naming the package to
/// install when its data is missing.
pub fn load(clip: &Clip) -> Result<Texture, CorpusError> {
    let err = |problem: String| CorpusError {
        clip: clip.name,
        problem,
    };
    let missing = |path: &str| {
        err(format!(
            "{path} not found: install Debian's {0} (apt-get install {0})",
            clip.package
        ))
    };
    let (x, rate) = match clip.source {
        Source::File(path) => {
            if !Path::new(path).is_file() {
                return Err(missing(path));
            }
            let r = trundle_io::recording::read_recording(Path::new(path))
                .map_err(|e| err(e.to_string()))?;
            (r.samples, r.sample_rate_hz)
        }
        Source::SoundFont(name) => {
            let sf2 = crate::data::FLUID_SF2;
            if !Path::new(sf2).is_file() {
                return Err(missing(sf2));
            }
            let s = read_sample(Path::new(sf2), name).map_err(err)?;
            (s.samples, f64::from(s.header.sample_rate_hz))
        }
    };
    let a = ((clip.start_s * rate).round() as usize).min(x.len());
    let b = clip
        .end_s
        .map_or(x.len(), |e| ((e * rate).round() as usize).min(x.len()))
        .max(a);
    Ok(Texture {
        samples: x[a..b].iter().map(|&v| v as f32).collect(),
        sample_rate_hz: rate.round() as u32,
    })
}
