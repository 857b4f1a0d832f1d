//! The core's one event loop (`trundle_dsp::scene::events`) driven the way the plugin and the CLI
//! drive it: the samples do not depend on how the host cuts its blocks (every size 1…8192,
//! and sizes changing every block), an event is never heard before its sample and lands on
//! the voice's control grid ([`trundle_dsp::block::CHUNK`] samples) right after it, and nothing
//! allocates while events are applied and blocks rendered.

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use trundle_dsp::block::CHUNK;
use trundle_dsp::scene::events::{process_with_events, TimedEvent, VoiceEvent};
use trundle_dsp::{ParamId, Params, Voice};

use trundle_test_support::alloc_guard::allocations_during;

const FS: f64 = 48_000.0;

/// Two balls and an automation step over 1.5 s, at offsets that are neither on the chunk
/// grid nor on any block size tried below; two events share a sample.
fn timeline() -> Vec<(usize, VoiceEvent)> {
    let mut slow = Params::default();
    slow.set(ParamId::Velocity, 0.2).unwrap();
    slow.set(ParamId::Roughness, 0.8).unwrap();
    vec![
        (
            0,
            VoiceEvent::NoteOn {
                note: 40,
                velocity: 0.5,
            },
        ),
        (
            4_801,
            VoiceEvent::NoteOn {
                note: 72,
                velocity: 0.9,
            },
        ),
        (4_801, VoiceEvent::Params(slow)),
        (33_333, VoiceEvent::NoteOff { note: 40 }),
        (61_441, VoiceEvent::NoteOff { note: 72 }),
    ]
}

/// Render `n` samples in blocks whose lengths `next_len` chooses, handing each block the
/// events that fall inside it (as a host does); returns the samples and the allocations
/// made while rendering.
fn render(
    events: &[(usize, VoiceEvent)],
    n: usize,
    mut next_len: impl FnMut() -> usize,
) -> (Vec<f32>, usize) {
    let mut voice = Voice::new(FS, &Params::default());
    let mut out = vec![0f32; n];
    let mut allocs = 0;
    let mut start = 0;
    while start < n {
        let len = next_len().clamp(1, n - start);
        let block = &mut out[start..start + len];
        let due = events
            .iter()
            .filter(|&&(at, _)| at >= start && at < start + len)
            .map(|&(at, event)| TimedEvent {
                offset: at - start,
                event,
            });
        allocs += allocations_during(|| process_with_events(&mut voice, block, due, |_, _, _| {}));
        start += len;
    }
    (out, allocs)
}

#[test]
fn any_block_size_gives_the_same_samples_without_allocating() {
    let events = timeline();
    let n = (1.5 * FS) as usize;
    let (whole, allocs) = render(&events, n, || n);
    assert_eq!(allocs, 0, "allocations in one block");
    assert!(whole.iter().any(|&x| x != 0.0), "the timeline is heard");
    // Fixed sizes around the chunk and the host's usual powers of two…
    let sizes = [1usize, 2, 3, 63, 64, 65, 127, 256, 1000, 4096, 8191, 8192];
    for size in sizes {
        let (out, allocs) = render(&events, n, || size);
        assert_eq!(allocs, 0, "allocations with blocks of {size}");
        assert!(out == whole, "blocks of {size} change the samples");
    }
    // …and sizes that change every block, anywhere in 1…8192.
    let mut rng = SmallRng::seed_from_u64(0x626c_6f63);
    for round in 0..8 {
        let (out, allocs) = render(&events, n, || rng.random_range(1..=8192));
        assert_eq!(allocs, 0, "allocations with random blocks (round {round})");
        assert!(
            out == whole,
            "random blocks (round {round}) change the samples"
        );
    }
}

/// First sample where `a` and `b` differ.
fn first_difference(a: &[f32], b: &[f32]) -> Option<usize> {
    a.iter().zip(b).position(|(x, y)| x != y)
}

#[test]
fn an_event_takes_effect_at_the_first_chunk_boundary_at_or_after_its_sample() {
    // The voice takes new targets and new balls at its control rate: one chunk of CHUNK
    // samples on a grid counted from the start (so that block size never matters, above).
    // An event at sample k is therefore never heard before k and acts from the first grid
    // point at or after k: at most CHUNK − 1 samples (1.3 ms at 48 kHz) late. A ball's first
    // impact comes some time after it starts, so "acts from" is tested as: the same note
    // placed exactly on that grid point gives the same samples, one chunk later does not.
    let n = 8 * 1024;
    let (plain, _) = render(&[], n, || 512);
    let note_at = |k: usize| {
        let on = [(
            k,
            VoiceEvent::NoteOn {
                note: 60,
                velocity: 0.8,
            },
        )];
        render(&on, n, || 300).0
    };
    let mut rng = SmallRng::seed_from_u64(0x6f6e_7365);
    let mut ks: Vec<usize> = (0..12).map(|_| rng.random_range(1..n / 2)).collect();
    ks.extend([1024, 1025, 1087, 1088]);
    for k in ks {
        let out = note_at(k);
        let grid = k.div_ceil(CHUNK) * CHUNK;
        let heard = first_difference(&out, &plain).expect("the note is heard");
        assert!(heard >= grid, "note at {k} heard at {heard}, before {grid}");
        assert!(
            out == note_at(grid),
            "note at {k} differs from one at {grid}"
        );
        assert!(
            out != note_at(grid + CHUNK),
            "note at {k} same as one at {}",
            grid + CHUNK
        );
    }
}

/// The CLI's path: a preset's automation lanes and ball notes become the events of each
/// block; how the render is cut into blocks must not show in the samples.
#[cfg(feature = "presets")]
#[test]
fn a_scene_with_every_block_size_renders_the_same_samples() {
    {
        use trundle_dsp::scene::events::Scene;
        use trundle_dsp::scene::preset::Lane;
        let lanes = [Lane {
            id: ParamId::Velocity,
            points: vec![(0.0, 0.1), (0.5, 1.0), (1.0, 0.3)],
        }];
        let notes = [
            (
                1_234u64,
                VoiceEvent::NoteOn {
                    note: 55,
                    velocity: 0.7,
                },
            ),
            (30_001, VoiceEvent::NoteOff { note: 55 }),
        ];
        let n = 48_000usize;
        let run = |mut next_len: Box<dyn FnMut() -> usize>| {
            let mut scene = Scene::new(Params::default(), &lanes, &notes, FS);
            let mut voice = Voice::new(FS, &scene.params_at(0));
            let mut out = vec![0f32; n];
            let mut done = 0;
            let mut allocs = 0;
            while done < n {
                let len = next_len().clamp(1, n - done);
                let block = &mut out[done..done + len];
                let events = scene.events(done as u64, len);
                allocs += allocations_during(|| {
                    process_with_events(&mut voice, block, events, |_, _, _| {})
                });
                done += len;
            }
            (out, allocs)
        };
        let (whole, allocs) = run(Box::new(move || n));
        assert_eq!(allocs, 0);
        let mut rng = SmallRng::seed_from_u64(0x7363_656e);
        for size in [1usize, 64, 100, 8192] {
            let (out, allocs) = run(Box::new(move || size));
            assert_eq!(allocs, 0, "allocations with blocks of {size}");
            assert!(out == whole, "blocks of {size} change the scene's samples");
        }
        let (out, allocs) = run(Box::new(move || rng.random_range(1..=8192)));
        assert_eq!(allocs, 0, "allocations with random blocks");
        assert!(out == whole, "random blocks change the scene's samples");
    }
}
