//! The editor's A/B compare: two snapshots of every table parameter and which one is being
//! edited.
//!
//! The live parameters always belong to the active slot. Switching stores the live values
//! into the active slot and hands back the other slot's snapshot for the editor to apply
//! (each changed parameter as a host gesture, so the host's undo sees the switch). A slot
//! never filled starts as a copy of the live values, so the first switch changes nothing
//! audible. [`AbCompare::copy_to_other`] makes the other slot a copy of the live values
//! (A→B while editing A).

use trundle_dsp::Params;

/// One of the two compare slots.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Slot {
    /// Slot A (active at first).
    #[default]
    A,
    /// Slot B.
    B,
}

impl Slot {
    /// The other slot.
    pub fn other(self) -> Slot {
        match self {
            Slot::A => Slot::B,
            Slot::B => Slot::A,
        }
    }

    /// "A" or "B".
    pub fn name(self) -> &'static str {
        match self {
            Slot::A => "A",
            Slot::B => "B",
        }
    }
}

/// Two parameter snapshots and the active slot.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AbCompare {
    slots: [Option<Params>; 2],
    active: Slot,
}

impl AbCompare {
    /// The slot the live parameters belong to.
    pub fn active(&self) -> Slot {
        self.active
    }

    /// The snapshot held in `slot` (the live values of the active slot are not in it until
    /// a switch or a copy stores them).
    pub fn snapshot(&self, slot: Slot) -> Option<&Params> {
        self.slots[slot as usize].as_ref()
    }

    /// Make `to` active: the `live` values are stored in the active slot and the values to
    /// apply are returned (`to`'s snapshot, or `live` itself for a slot never filled).
    /// Switching to the active slot returns `live` unchanged.
    pub fn switch_to(&mut self, to: Slot, live: &Params) -> Params {
        if to == self.active {
            return *live;
        }
        self.slots[self.active as usize] = Some(*live);
        self.active = to;
        *self.slots[to as usize].get_or_insert(*live)
    }

    /// Copy the `live` values (the active slot's) into the other slot.
    pub fn copy_to_other(&mut self, live: &Params) {
        self.slots[self.active as usize] = Some(*live);
        self.slots[self.active.other() as usize] = Some(*live);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use trundle_dsp::ParamId;

    fn with(id: ParamId, v: f64) -> Params {
        let mut p = Params::default();
        p.set(id, v).unwrap();
        p
    }

    #[test]
    fn switching_keeps_each_slots_edits() {
        let mut ab = AbCompare::default();
        assert_eq!(ab.active(), Slot::A);
        let a = with(ParamId::Velocity, 0.2);
        // B was never filled: it starts as a copy of A.
        assert_eq!(ab.switch_to(Slot::B, &a), a);
        assert_eq!(ab.active(), Slot::B);
        // Edit B, switch back: A's values return, B's edits are kept.
        let b = with(ParamId::Velocity, 0.8);
        assert_eq!(ab.switch_to(Slot::A, &b), a);
        assert_eq!(ab.snapshot(Slot::B), Some(&b));
        assert_eq!(ab.switch_to(Slot::B, &a), b);
        // Switching to the active slot changes nothing.
        assert_eq!(ab.switch_to(Slot::B, &b), b);
        assert_eq!(ab.active(), Slot::B);
    }

    #[test]
    fn copy_makes_the_other_slot_the_live_values() {
        let mut ab = AbCompare::default();
        let a = with(ParamId::Decay, 3.0);
        ab.copy_to_other(&a);
        assert_eq!(ab.snapshot(Slot::B), Some(&a));
        let a2 = with(ParamId::Decay, 0.5);
        assert_eq!(ab.switch_to(Slot::B, &a2), a);
        assert_eq!(ab.snapshot(Slot::A), Some(&a2));
        assert_eq!(Slot::A.other(), Slot::B);
        assert_eq!(Slot::B.name(), "B");
    }
}
