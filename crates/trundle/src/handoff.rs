//! A value handed from the main/GUI thread to the audio thread without a lock or an
//! allocation there: what the fitted object ([`crate::object_slot`]) and the body EQ curve
//! ([`crate::body_eq_slot`]) ride on.
//!
//! ```text
//!  main / GUI thread ──set()──► publish: pointer store, then generation + 1
//!  audio thread, every block:  generation changed? ──► load() (two atomic loads and a
//!                                                      reference count: no allocation)
//! ```
//!
//! The handoff publishes a raw pointer to a value it keeps alive itself: every value it ever
//! published stays referenced here ("retired") until the audio thread has acknowledged a
//! later generation (so it can no longer be reading that pointer) and holds no reference of
//! its own — so the audio thread never frees memory and never reads a freed value. (A
//! lock-free `Arc` swap crate was tried first: it allocates a per-thread record the first
//! time a thread reads, which nice-plug's allocation check caught on the audio thread.)

use std::sync::atomic::{AtomicPtr, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

/// The published value and the ones it replaced (main/GUI threads only).
struct Held<T> {
    /// The published value (keeps the pointee of `published` alive).
    current: Option<Arc<T>>,
    /// Values published before, with the generation that replaced them: kept until the
    /// audio thread has acknowledged that generation and let go of them.
    retired: Vec<(u64, Arc<T>)>,
}

impl<T> Default for Held<T> {
    fn default() -> Self {
        Self {
            current: None,
            retired: Vec::new(),
        }
    }
}

/// One value (or none) shared by the main/GUI threads and read by the audio thread
/// lock-free (module docs).
pub struct Handoff<T> {
    /// Main/GUI threads only (never locked by the audio thread).
    held: Mutex<Held<T>>,
    /// What the audio thread reads: `Arc::as_ptr` of `held.current`, null for none.
    published: AtomicPtr<T>,
    /// Bumped after every publish; the audio thread compares it with the one it applied.
    generation: AtomicU64,
    /// The last generation the audio thread applied ([`Handoff::load`]).
    acknowledged: AtomicU64,
}

impl<T> Default for Handoff<T> {
    fn default() -> Self {
        Self {
            held: Mutex::new(Held::default()),
            published: AtomicPtr::new(std::ptr::null_mut()),
            generation: AtomicU64::new(0),
            acknowledged: AtomicU64::new(0),
        }
    }
}

impl<T> Handoff<T> {
    /// Publish `value` (`None`: nothing). Main/GUI thread: locks and may free values the
    /// audio thread has let go of; never call from `process`.
    pub fn set(&self, value: Option<Arc<T>>) {
        let mut held = self.held.lock().unwrap_or_else(|e| e.into_inner());
        let acknowledged = self.acknowledged.load(Ordering::Acquire);
        // Values the audio thread can no longer be reading (it has applied a later
        // generation) and no longer holds (only this handoff references them) can go.
        held.retired
            .retain(|(replaced_at, o)| *replaced_at > acknowledged || Arc::strong_count(o) > 1);
        let next = self.generation.load(Ordering::Relaxed) + 1;
        let ptr = value
            .as_ref()
            .map_or(std::ptr::null_mut(), |o| Arc::as_ptr(o).cast_mut());
        if let Some(old) = std::mem::replace(&mut held.current, value) {
            held.retired.push((next, old));
        }
        // The pointer first, then the generation: a reader that sees the new generation
        // sees the new pointer.
        self.published.store(ptr, Ordering::Release);
        self.generation.store(next, Ordering::Release);
    }

    /// The value published, if any (main/GUI thread).
    pub fn current(&self) -> Option<Arc<T>> {
        self.held
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .current
            .clone()
    }

    /// The generation of the last publish (audio thread: cheap, lock-free).
    pub fn generation(&self) -> u64 {
        self.generation.load(Ordering::Acquire)
    }

    /// The value of generation `generation` (from [`Handoff::generation`]) to use now,
    /// acknowledging it (audio thread: lock-free, no allocation).
    pub fn load(&self, generation: u64) -> Option<Arc<T>> {
        let ptr = self.published.load(Ordering::Acquire);
        let value = if ptr.is_null() {
            None
        } else {
            // SAFETY: `ptr` came from `Arc::as_ptr` of an Arc this handoff holds (`current`,
            // or `retired` until a generation after the one that replaced it is
            // acknowledged below, which happens only after this count is taken), so the
            // pointee is alive and its count can be incremented and owned here.
            unsafe {
                Arc::increment_strong_count(ptr);
                Some(Arc::from_raw(ptr))
            }
        };
        self.acknowledged.fetch_max(generation, Ordering::Release);
        value
    }

    /// How many replaced values are still kept alive (tests).
    #[cfg(test)]
    pub(crate) fn retired(&self) -> Vec<Arc<T>> {
        let held = self.held.lock().unwrap_or_else(|e| e.into_inner());
        held.retired.iter().map(|(_, v)| v.clone()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_audio_thread_never_drops_the_last_reference() {
        let h = Handoff::<Vec<u8>>::default();
        assert!(h.load(0).is_none());
        h.set(Some(Arc::new(vec![1, 2, 3])));
        // What the audio thread holds after applying the publish.
        let held_by_voice = h.load(h.generation()).unwrap();
        h.set(None);
        // Not yet acknowledged: the handoff keeps its reference, so the voice's drop (when
        // it lets go of the value) frees nothing on the audio thread.
        assert!(Arc::strong_count(&held_by_voice) >= 2);
        assert!(h.load(h.generation()).is_none());
        drop(held_by_voice);
        // Acknowledged and let go of: the next publish frees it (here, not on audio).
        h.set(None);
        assert!(h.retired().is_empty());
    }

    #[test]
    fn a_reader_between_two_publishes_keeps_a_live_value() {
        // The audio thread read generation 1's pointer but has not acknowledged anything
        // newer: the replaced value must stay alive whatever the GUI publishes meanwhile.
        let h = Handoff::<Vec<u8>>::default();
        h.set(Some(Arc::new(vec![7; 16])));
        let g1 = h.generation();
        let first = h.load(g1).unwrap();
        for i in 0..3 {
            h.set(Some(Arc::new(vec![i; 16])));
        }
        assert_eq!(first[..], [7; 16], "still alive and readable");
        assert_eq!(h.retired().len(), 3);
        drop(first);
        let latest = h.load(h.generation()).unwrap();
        h.set(None);
        // Everything older than the acknowledged generation and unreferenced is gone; the
        // one the reader holds stays.
        let retired = h.retired();
        assert_eq!(retired.len(), 1);
        assert!(Arc::ptr_eq(&retired[0], &latest));
    }
}
