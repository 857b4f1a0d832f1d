//! Expression per ball through the real CLAP bundle (#13): CLAP note expressions reach the
//! ball of their note and no other, and the plugin tells the host when a ball has ended.

use trundle_tests::check::{first_difference, load_bundle, new_instance, rms};
use trundle_tests::{Block, Instance, NoteExpression, NoteExpressionType, Transport};

const FS: f64 = 48_000.0;
const BLOCK: usize = 512;

/// One ball (key 60, velocity 0.5) with the transport stopped (the scene's own ball rests),
/// `seconds` long, the note off at `off_block` if given, `expressions` sent at block 47
/// (0.5 s). Returns the left channel and the note ends the plugin reported.
fn ball(
    inst: &mut Instance,
    seconds: f64,
    expressions: Vec<NoteExpression>,
    off_block: Option<usize>,
) -> (Vec<f32>, Vec<(usize, u8)>) {
    inst.activate(FS, BLOCK).unwrap();
    let n = (seconds * FS / BLOCK as f64) as usize;
    let blocks: Vec<Block> = (0..n)
        .map(|i| Block {
            len: BLOCK,
            events: Vec::new(),
            transport: Transport::Stopped,
            notes: match (i, off_block) {
                (0, _) => vec![(0, 60, Some(0.5))],
                (i, Some(off)) if i == off => vec![(0, 60, None)],
                _ => Vec::new(),
            },
        })
        .collect();
    let mut per_block = vec![Vec::new(); n];
    per_block[47] = expressions;
    inst.send_expressions(per_block);
    let [left, _] = inst.render(&blocks).unwrap();
    let ends = inst.take_note_ends();
    inst.deactivate().unwrap();
    (left, ends)
}

#[test]
fn note_expressions_reach_their_ball_and_only_it() {
    let b = load_bundle();
    let mut inst = new_instance(&b);
    let (plain, _) = ball(&mut inst, 2.0, Vec::new(), None);
    assert!(rms(&plain) > 1e-4, "the MIDI ball is silent");

    // Full pressure on key 60: the ball leans on the surface, +6 dB once the object has
    // rung out what it was struck with before (the last second; 0.5 % as in the engine's
    // own test, trundle-dsp tests/balls.rs).
    let (pressed, _) = ball(
        &mut inst,
        2.0,
        vec![(0, 60, NoteExpressionType::Pressure, 1.0)],
        None,
    );
    let tail = FS as usize;
    let ratio = rms(&pressed[tail..]) / rms(&plain[tail..]);
    println!("pressure 1 through CLAP: ×{ratio:.4}");
    assert!((ratio - 2.0).abs() < 0.01, "ratio {ratio}");

    // Brightness (timbre → roughness) changes the sound of that ball.
    let (bright, _) = ball(
        &mut inst,
        2.0,
        vec![(0, 60, NoteExpressionType::Brightness, 1.0)],
        None,
    );
    assert!(first_difference(&bright, &plain).is_some());

    // Addressed to a key no ball plays: nothing changes, bit for bit.
    let (other, _) = ball(
        &mut inst,
        2.0,
        vec![(0, 61, NoteExpressionType::Pressure, 1.0)],
        None,
    );
    assert_eq!(first_difference(&other, &plain), None);
}

#[test]
fn a_ball_that_rolled_to_rest_is_reported_to_the_host() {
    let b = load_bundle();
    let mut inst = new_instance(&b);
    // Note off at 0.5 s: V 0.5 rolls to rest in about 0.6 s (1.5 m/s², then the soft
    // settle), so the note ends well inside the 3 s.
    let (_, ends) = ball(&mut inst, 3.0, Vec::new(), Some(47));
    assert_eq!(ends.len(), 1, "{ends:?}");
    let (block, key) = ends[0];
    assert_eq!(key, 60);
    let t = block as f64 * BLOCK as f64 / FS;
    println!("note end at {t:.2} s (note off at 0.50 s)");
    assert!((0.8..2.5).contains(&t), "ended at {t} s");
    // Held: no end.
    let (_, ends) = ball(&mut inst, 1.5, Vec::new(), None);
    assert!(ends.is_empty(), "{ends:?}");
}
