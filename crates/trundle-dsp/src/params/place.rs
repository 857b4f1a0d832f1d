//! Where a control shows: properties of a table row for the surfaces that draw it.
//!
//! The model does not draw anything; these are plain data the plugin reads (its editor lays
//! each panel out from the rows placed in it, its randomize button draws the rows of each
//! group), so adding a control is one row of the table, not a row plus lists kept in the
//! editor and the randomizer.

/// A panel of the plugin editor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Panel {
    /// The rub–scratch–roll disk (main page).
    Action,
    /// The wood–metal–glass disk (main page).
    Material,
    /// The object seen from above: the ball, the listening point, the path (main page).
    Position,
    /// The ball's knobs and selectors (main page).
    Ball,
    /// The object's knobs and its shape (main page).
    Object,
    /// Level, stereo width, output, seed, limiter (main page).
    Output,
    /// The motion page: gesture, surface, crowd and cost.
    Motion,
}

/// The pages of the plugin editor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Page {
    /// Disks, position, spectrum; ball, object, output.
    Main,
    /// How the ball moves, what it rolls on, how many roll, at what cost.
    Motion,
}

impl Panel {
    /// The page this panel is on.
    pub const fn page(self) -> Page {
        match self {
            Panel::Motion => Page::Motion,
            _ => Page::Main,
        }
    }
}

/// A section of a panel: the controls drawn together, in the order of the variants here
/// (and in table order within a section).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Section {
    /// A main-page panel's row of knobs.
    Knobs,
    /// The column beside a main-page panel's knobs (selectors, fields, switches).
    Side,
    /// A disk or the position pad and the controls under it.
    Pad,
    /// Motion page: the gesture (roll, drop, spin) and its times and heights.
    Gesture,
    /// Motion page: what the ball rolls on and the gravity paths' time.
    Surface,
    /// Motion page: how many balls roll together.
    Crowd,
    /// Motion page: the accuracy/cost budget.
    Quality,
}

impl Section {
    /// The section's title in the editor.
    pub const fn title(self) -> &'static str {
        match self {
            Section::Knobs => "Knobs",
            Section::Side => "Side",
            Section::Pad => "Pad",
            Section::Gesture => "Gesture",
            Section::Surface => "Surface",
            Section::Crowd => "Crowd",
            Section::Quality => "Quality",
        }
    }
}

/// Where the editor draws a row: a panel, a section of it and the control's caption there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Place {
    /// The panel.
    pub panel: Panel,
    /// The section of the panel.
    pub section: Section,
    /// The control's short caption in its section (the row's full name is in its tooltip).
    pub label: &'static str,
}

/// A place: `panel`, `section`, caption `label`.
pub const fn at(panel: Panel, section: Section, label: &'static str) -> Place {
    Place {
        panel,
        section,
        label,
    }
}

/// The groups the randomize button draws and locks together.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Group {
    /// The ball: size, velocity, roughness, asymmetry, sharpness, material, AM law.
    Ball,
    /// The action disk (rub · scratch · roll).
    Action,
    /// The object: material disk, size, shape, modes, decay.
    Object,
    /// Where the ball rolls and where it is heard: position, listening point, trajectory,
    /// position amount.
    Position,
    /// Stereo width and the random seed.
    Output,
}

impl Group {
    /// Every group, in the editor's order.
    pub const ALL: [Group; 5] = [
        Group::Ball,
        Group::Action,
        Group::Object,
        Group::Position,
        Group::Output,
    ];

    /// The group's name in the editor.
    pub fn name(self) -> &'static str {
        match self {
            Group::Ball => "Ball",
            Group::Action => "Action",
            Group::Object => "Object",
            Group::Position => "Position",
            Group::Output => "Width + seed",
        }
    }
}
