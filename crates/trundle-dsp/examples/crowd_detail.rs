//! The crowd's level-of-detail trade, measured (docs/guide/scenes.md "A thousand balls"):
//! `cargo run --release -p trundle-dsp --example crowd_detail`.
//!
//! For crowds of 64 and 1000 balls (spread 0.5, the default scene), the crowd's force is
//! rendered with every ball a whole source (the reference: `Crowd::new` with room for all
//! of them) and at `crowd_detail` 0, 4, 8 and 16; it prints the cost (ns per output sample of
//! the crowd's force alone, best of three) and the worst third-octave difference from the
//! reference, 100 Hz–12.5 kHz (dB; the tests' band measure, `trundle_test_support::bands`).

use std::time::Instant;
use trundle_dsp::block::CHUNK;
use trundle_dsp::scene::crowd::{Crowd, CrowdControls};
use trundle_dsp::source::chain::SourceControls;
use trundle_test_support::bands::third_octave_db_between;

const FS: f64 = 48_000.0;
const SECONDS: f64 = 10.0;

fn render(count: usize, detail: usize, max_detail: usize) -> (Vec<f32>, f64) {
    let sc = SourceControls::default();
    let mut best = f64::INFINITY;
    let mut y = Vec::new();
    for _ in 0..3 {
        let mut c = Crowd::new(FS, max_detail, 7);
        c.set_controls(CrowdControls {
            count,
            spread: 0.5,
            detail,
        });
        c.snap_controls(sc);
        // Let every ball join (at most 64 a chunk) before timing.
        let mut warm = [0.0f32; CHUNK];
        for _ in 0..32 {
            warm.fill(0.0);
            c.add_chunk(&mut warm, sc);
        }
        y = vec![0.0f32; (SECONDS * FS) as usize / CHUNK * CHUNK];
        let t = Instant::now();
        for b in y.chunks_mut(CHUNK) {
            c.add_chunk(b, sc);
        }
        best = best.min(t.elapsed().as_nanos() as f64 / y.len() as f64);
    }
    (y, best)
}

fn main() {
    println!("| balls | crowd_detail | ns/sample (crowd force) | × real time | worst third-octave difference (dB) |");
    println!("|---:|---:|---:|---:|---:|");
    for count in [64, 1000] {
        let (reference, ref_ns) = render(count, count - 1, count - 1);
        let bands = third_octave_db_between(&reference, FS, 100.0, 12_500.0);
        println!(
            "| {count} | all ({}) | {ref_ns:.0} | {:.1} | 0 (reference) |",
            count - 1,
            1e9 / FS / ref_ns
        );
        for detail in [16, 8, 4, 0] {
            let (y, ns) = render(count, detail, 16);
            let worst = bands
                .iter()
                .zip(third_octave_db_between(&y, FS, 100.0, 12_500.0))
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            println!(
                "| {count} | {detail} | {ns:.0} | {:.1} | {worst:.2} |",
                1e9 / FS / ns
            );
        }
    }
}
