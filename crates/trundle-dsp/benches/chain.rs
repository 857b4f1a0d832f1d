//! Cost of the full chain per output sample (DESIGN "Speed and accuracy").
//!
//! * `voice/{8,32,128}`: a [`Voice`] with default parameters (rolling, plate, wood-ish
//!   material, 48 kHz) and `modes` = 8, 32 or 128, rendering blocks of 512 samples — series,
//!   pulses, AM, velocity low-pass and the modal object, everything a host pays for.
//! * `modal_bank/128`: the Mathews–Smith bank alone, 128 modes, driven the way the object
//!   drives it (chunks of [`CHUNK`] samples, state flushed between chunks).
//!
//! Throughput is in output samples, so criterion's "elem/s" inverts to ns per output
//! sample. Run with `cargo bench -p trundle-dsp --bench chain` (about 30 s).

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_main, BenchmarkId, Criterion, Throughput};
use trundle_dsp::modal::{phasor_coeffs, ModalBank, ModeCoeffs};
use trundle_dsp::{ParamId, Params, Voice, CHUNK};

const FS: f64 = 48_000.0;
const BLOCK: usize = 512;

fn voice(c: &mut Criterion) {
    let mut group = c.benchmark_group("voice");
    group.throughput(Throughput::Elements(BLOCK as u64));
    for modes in [8usize, 32, 128] {
        let mut p = Params::default();
        p.set(ParamId::Modes, modes as f64).expect("modes in range");
        let mut v = Voice::new(FS, &p);
        let mut buf = vec![0f32; BLOCK];
        // Warm the voice past its onset so every mode is sounding.
        for _ in 0..200 {
            v.process(&mut buf);
        }
        assert_eq!(v.object().active_modes(), modes, "modes not all active");
        group.bench_with_input(BenchmarkId::from_parameter(modes), &modes, |b, _| {
            b.iter(|| {
                v.process(&mut buf);
                black_box(&buf);
            })
        });
    }
    group.finish();
}

fn modal_bank(c: &mut Criterion) {
    const MODES: usize = 128;
    let mut group = c.benchmark_group("modal_bank");
    group.throughput(Throughput::Elements(BLOCK as u64));
    let mut bank = ModalBank::new(MODES);
    for k in 0..MODES {
        let f = 100.0 * (1.0 + 0.61 * k as f64);
        let (c, s) = phasor_coeffs(f, 0.5, FS);
        bank.set_mode(k, ModeCoeffs { c, s, g: 1e-3 });
    }
    bank.set_active(MODES);
    // A fixed pseudo-random force (a linear congruential generator: no dependency).
    let mut state = 1u32;
    let input: Vec<f32> = (0..BLOCK)
        .map(|_| {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32 - 0.5
        })
        .collect();
    let mut out = vec![0f32; BLOCK];
    group.bench_with_input(BenchmarkId::from_parameter(MODES), &MODES, |b, _| {
        b.iter(|| {
            for (x, y) in input.chunks(CHUNK).zip(out.chunks_mut(CHUNK)) {
                bank.process(black_box(x), y);
                bank.flush();
            }
            black_box(&out);
        })
    });
    group.finish();
}

fn benches() {
    let mut c = Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
        .configure_from_args();
    voice(&mut c);
    modal_bank(&mut c);
}

criterion_main!(benches);
