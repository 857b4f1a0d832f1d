//! Cost of the full chain per output sample (docs/MODEL.md "Speed and accuracy").
//!
//! * `voice/{8,32,128}`: a [`Voice`] with default parameters (rolling, plate, wood-ish
//!   material, 48 kHz) and `modes` = 8, 32 or 128, rendering blocks of 512 samples — series,
//!   pulses, AM, velocity low-pass and the modal object, everything a host pays for.
//! * `voice_physics/32`: the same with `engine = physics` (Hunt–Crossley ball, RK4).
//! * `voice_idle/32`: a voice whose ball is at rest and whose object has decayed (the
//!   silence skip).
//! * `modal_bank/{kernel}/{8,32,128}`: the Mathews–Smith bank alone, driven the way the
//!   object drives it (chunks of [`CHUNK`] samples, state flushed between chunks), with
//!   every kernel this CPU runs ([`Kernel`]). Divide ns per element by the mode count for
//!   ns per mode·sample.
//!
//! Throughput is in output samples, so criterion's "elem/s" inverts to ns per output
//! sample. Run with `cargo bench -p trundle-dsp --bench chain` (about a minute; add
//! `-- --quick` for a rough pass).

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_main, BenchmarkId, Criterion, Throughput};
use trundle_dsp::block::CHUNK;
use trundle_dsp::object::bank::{phasor_coeffs, ModalBank, ModeCoeffs};
use trundle_dsp::object::kernels::Kernel;
use trundle_dsp::{ParamId, Params, Voice};

const FS: f64 = 48_000.0;
const BLOCK: usize = 512;

fn voice_with(modes: usize, engine: &str) -> Voice {
    let mut p = Params::default();
    p.set(ParamId::Modes, modes as f64).expect("modes in range");
    p.set_text("engine", engine).expect("engine parameter");
    let mut v = Voice::new(FS, &p);
    let mut buf = vec![0f32; BLOCK];
    // Warm the voice past its onset so every mode is sounding.
    for _ in 0..200 {
        v.process(&mut buf);
    }
    v
}

fn voice(c: &mut Criterion) {
    let mut group = c.benchmark_group("voice");
    group.throughput(Throughput::Elements(BLOCK as u64));
    for modes in [8usize, 32, 128] {
        let mut v = voice_with(modes, "signal");
        assert_eq!(v.object().active_modes(), modes, "modes not all active");
        let mut buf = vec![0f32; BLOCK];
        group.bench_with_input(BenchmarkId::from_parameter(modes), &modes, |b, _| {
            b.iter(|| {
                v.process(&mut buf);
                black_box(&buf);
            })
        });
    }
    group.finish();

    let mut group = c.benchmark_group("voice_physics");
    group.throughput(Throughput::Elements(BLOCK as u64));
    let mut v = voice_with(32, "physics");
    let mut buf = vec![0f32; BLOCK];
    group.bench_function(BenchmarkId::from_parameter(32), |b| {
        b.iter(|| {
            v.process(&mut buf);
            black_box(&buf);
        })
    });
    group.finish();

    let mut group = c.benchmark_group("voice_idle");
    group.throughput(Throughput::Elements(BLOCK as u64));
    let mut v = voice_with(32, "signal");
    let mut p = *v.params();
    p.set(ParamId::Velocity, 0.0).expect("velocity in range");
    v.set_params(&p);
    // Let the ball stop and the object ring out.
    for _ in 0..2_000 {
        v.process(&mut buf);
    }
    group.bench_function(BenchmarkId::from_parameter(32), |b| {
        b.iter(|| {
            v.process(&mut buf);
            black_box(&buf);
        })
    });
    group.finish();
}

/// A bank of `modes` modes as an object would set it (100 Hz upwards, τ = 0.5 s).
fn bench_bank(modes: usize, kernel: Kernel) -> ModalBank {
    let mut bank = ModalBank::new(modes);
    assert!(bank.set_kernel(kernel));
    for k in 0..modes {
        let f = 100.0 * (1.0 + 0.61 * k as f64);
        let (c, s) = phasor_coeffs(f, 0.5, FS);
        bank.set_mode(
            k,
            ModeCoeffs {
                c,
                s,
                g: 1e-3,
                h: 0.0,
                d: 0.0,
            },
        );
    }
    bank.set_active(modes);
    bank
}

fn modal_bank(c: &mut Criterion) {
    // A fixed pseudo-random force (a linear congruential generator: no dependency).
    let mut state = 1u32;
    let input: Vec<f32> = (0..BLOCK)
        .map(|_| {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32 - 0.5
        })
        .collect();
    let mut out = vec![0f32; BLOCK];
    for kernel in Kernel::ALL.into_iter().filter(|k| k.is_available()) {
        let mut group = c.benchmark_group(format!("modal_bank/{}", kernel.name()));
        group.throughput(Throughput::Elements(BLOCK as u64));
        for modes in [8usize, 32, 128] {
            let mut bank = bench_bank(modes, kernel);
            group.bench_with_input(BenchmarkId::from_parameter(modes), &modes, |b, _| {
                b.iter(|| {
                    for (x, y) in input.chunks(CHUNK).zip(out.chunks_mut(CHUNK)) {
                        bank.process(black_box(x), y);
                        bank.flush();
                    }
                    black_box(&out);
                })
            });
        }
        group.finish();
    }
}

fn benches() {
    let mut c = Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
        .configure_from_args();
    modal_bank(&mut c);
    voice(&mut c);
}

criterion_main!(benches);
