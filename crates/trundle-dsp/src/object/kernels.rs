//! The inner loop of the modal bank ([`crate::object::bank`]): the data layout (modes in
//! groups of [`LANES`], a per-sample, per-lane accumulator of [`BLOCK`] rows) and the
//! kernels that run the Mathews–Smith recursion over it, chosen at run time
//! ([`Kernel::detect`]):
//!
//! | kernel | where | arithmetic |
//! |---|---|---|
//! | [`Kernel::Avx2Fma`] | x86-64 with AVX2 and FMA | 8 lanes per register, fused multiply–add |
//! | [`Kernel::Sse2`] | any x86-64 | 4 lanes per register, separate multiply and add |
//! | [`Kernel::Scalar`] | everywhere | plain Rust (the reference) |
//!
//! The SSE2 and scalar kernels perform the same operations in the same order and give
//! bit-identical output; the FMA kernel rounds twice instead of four times per update, so it
//! differs from them by a few f32 ulps per sample (bounded in the bank's tests over long,
//! high-Q runs). All three accumulate the modes in the same order.
//!
//! Each kernel comes in two variants (const generic `PH`): real input gains (the recipe
//! objects: the input enters Re z only) and complex ones (fitted objects played with their
//! phase: the input also enters Im z with gain h, one more multiply–add per mode·sample).
//! The bank runs the complex variant only while some mode has h ≠ 0, so objects with real
//! gains run exactly the arithmetic they always ran.

/// Modes processed together; the bank's capacity is padded to a multiple of this.
pub const LANES: usize = 8;

/// Largest number of samples the kernels process in one pass (the size of the stack
/// accumulator); longer inputs are split.
pub const BLOCK: usize = crate::block::CHUNK;

/// A per-sample, per-lane accumulator, aligned for 256-bit loads and stores.
#[derive(Clone)]
#[repr(C, align(32))]
pub(crate) struct Acc(pub(crate) [[f32; LANES]; BLOCK]);

impl core::fmt::Debug for Acc {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("Acc")
    }
}

/// An implementation of the bank's inner loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kernel {
    /// Portable Rust; the reference the others are tested against.
    Scalar,
    /// x86-64 SSE2 intrinsics (every x86-64 CPU has SSE2); bit-identical to `Scalar`.
    Sse2,
    /// x86-64 AVX2 + FMA intrinsics, chosen at run time when the CPU has both.
    Avx2Fma,
}

impl Kernel {
    /// Every kernel, fastest first.
    pub const ALL: [Kernel; 3] = [Kernel::Avx2Fma, Kernel::Sse2, Kernel::Scalar];

    /// The fastest kernel this CPU runs (`is_x86_feature_detected!`, cached by std).
    pub fn detect() -> Self {
        Self::ALL
            .into_iter()
            .find(|k| k.is_available())
            .unwrap_or(Kernel::Scalar)
    }

    /// True when this CPU can run the kernel.
    pub fn is_available(self) -> bool {
        match self {
            Kernel::Scalar => true,
            #[cfg(target_arch = "x86_64")]
            Kernel::Sse2 => true,
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx2Fma => {
                std::arch::is_x86_feature_detected!("avx2")
                    && std::arch::is_x86_feature_detected!("fma")
            }
            #[cfg(not(target_arch = "x86_64"))]
            Kernel::Sse2 | Kernel::Avx2Fma => false,
        }
    }

    /// A short name ("avx2+fma", "sse2", "scalar").
    pub fn name(self) -> &'static str {
        match self {
            Kernel::Scalar => "scalar",
            Kernel::Sse2 => "sse2",
            Kernel::Avx2Fma => "avx2+fma",
        }
    }
}

impl Kernel {
    /// Run `m` over the input chunk `x` (at most [`BLOCK`] samples), adding each group's
    /// lanes into `acc` (and, `ST`, the side into `side`). `PH`: the input also enters the
    /// imaginary part of the state with gain `h` (complex input gains, one more multiply–add
    /// per mode·sample); without it `h` is not read and the arithmetic is exactly the
    /// real-gain kernel's. The caller checked [`is_available`](Self::is_available).
    #[inline]
    pub(crate) fn run<const ST: bool, const PH: bool>(
        self,
        m: &mut Modes<'_>,
        x: &[f32],
        acc: &mut Acc,
        side: &mut Acc,
    ) {
        match self {
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx2Fma => x86::avx2_fma::<ST, PH>(m, x, acc, side),
            #[cfg(target_arch = "x86_64")]
            Kernel::Sse2 => x86::sse2::<ST, PH>(m, x, acc, side),
            _ => scalar::<ST, PH>(m, x, acc, side),
        }
    }
}

/// The processed part of the bank's arrays (all the same length, a multiple of [`LANES`]).
pub(crate) struct Modes<'a> {
    pub(crate) re: &'a mut [f32],
    pub(crate) im: &'a mut [f32],
    pub(crate) c: &'a [f32],
    pub(crate) s: &'a [f32],
    pub(crate) g: &'a [f32],
    /// Imaginary input gains (read only by the `PH` kernels).
    pub(crate) h: &'a [f32],
    pub(crate) d: &'a [f32],
}

/// The lanes of one accumulator row, summed in a fixed order.
#[inline]
pub(crate) fn lane_sum(a: &[f32; LANES]) -> f32 {
    ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]))
}

/// `out[t] = lane_sum(rows[t])` for every row: with the AVX2 kernel, four rows at a time by
/// horizontal adds in [`lane_sum`]'s order (bit for bit the same sums).
#[inline]
pub(crate) fn lane_sums(kernel: Kernel, rows: &[[f32; LANES]], out: &mut [f32]) {
    #[cfg(target_arch = "x86_64")]
    {
        if kernel == Kernel::Avx2Fma {
            // SAFETY: the AVX2+FMA kernel is only selected where the CPU has AVX2 (and so
            // AVX): `set_kernel` refuses a kernel the CPU lacks.
            unsafe { x86::avx_lane_sums(rows, out) };
            return;
        }
    }
    let _ = kernel;
    for (y, a) in out.iter_mut().zip(rows) {
        *y = lane_sum(a);
    }
}

/// The reference kernel: for each group of [`LANES`] modes, for each sample,
/// `z ← p·z + g·x` (`PH`: `z ← p·z + (g + i·h)·x`), `acc[t] += Im z` (and, stereo,
/// `side[t] += d·Im z`), in exactly the order the SSE2 kernel uses.
fn scalar<const ST: bool, const PH: bool>(
    m: &mut Modes<'_>,
    x: &[f32],
    acc: &mut Acc,
    side: &mut Acc,
) {
    for o in (0..m.c.len()).step_by(LANES) {
        let lanes = o..o + LANES;
        let c: [f32; LANES] = m.c[lanes.clone()].try_into().expect("whole group");
        let s: [f32; LANES] = m.s[lanes.clone()].try_into().expect("whole group");
        let g: [f32; LANES] = m.g[lanes.clone()].try_into().expect("whole group");
        let d: [f32; LANES] = m.d[lanes.clone()].try_into().expect("whole group");
        let h: [f32; LANES] = if PH {
            m.h[lanes.clone()].try_into().expect("whole group")
        } else {
            [0.0; LANES]
        };
        let mut re: [f32; LANES] = m.re[lanes.clone()].try_into().expect("whole group");
        let mut im: [f32; LANES] = m.im[lanes.clone()].try_into().expect("whole group");
        for (t, &xt) in x.iter().enumerate() {
            for l in 0..LANES {
                let nr = (c[l] * re[l] - s[l] * im[l]) + g[l] * xt;
                let ni = if PH {
                    (s[l] * re[l] + c[l] * im[l]) + h[l] * xt
                } else {
                    s[l] * re[l] + c[l] * im[l]
                };
                re[l] = nr;
                im[l] = ni;
                acc.0[t][l] += ni;
                if ST {
                    side.0[t][l] += d[l] * ni;
                }
            }
        }
        m.re[lanes.clone()].copy_from_slice(&re);
        m.im[lanes].copy_from_slice(&im);
    }
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    //! The x86-64 kernels. Each processes `G` groups of [`LANES`] modes at once (so `2·G`
    //! independent recursions hide the multiply–add latency), then the remaining groups one
    //! at a time, in group order (so the accumulation order equals the scalar kernel's).

    use super::{Acc, Modes, BLOCK, LANES};
    use std::arch::x86_64::*;

    /// [`super::lane_sum`] of every row into `out` (the shorter sets the count), four rows
    /// at a time: `hadd` pairs (a₀+a₁, a₂+a₃ | a₄+a₅, a₆+a₇) of two rows, `hadd` again gives
    /// (a₀+a₁)+(a₂+a₃) and (a₄+a₅)+(a₆+a₇) of four rows in the two 128-bit halves, whose
    /// sum is `lane_sum`'s last addition: the same additions in the same order.
    ///
    /// # Safety
    /// The CPU must have AVX.
    #[target_feature(enable = "avx")]
    #[allow(unused_unsafe)] // as avx2_groups
    pub(super) unsafe fn avx_lane_sums(rows: &[[f32; LANES]], out: &mut [f32]) {
        let n = rows.len().min(out.len());
        let (rows, out) = (&rows[..n], &mut out[..n]);
        let mut quads = rows.chunks_exact(4);
        let mut outs = out.chunks_exact_mut(4);
        for (r, y) in (&mut quads).zip(&mut outs) {
            // SAFETY: each row is 8 f32 (one unaligned 256-bit load), `y` holds 4 f32.
            unsafe {
                let h01 = _mm256_hadd_ps(
                    _mm256_loadu_ps(r[0].as_ptr()),
                    _mm256_loadu_ps(r[1].as_ptr()),
                );
                let h23 = _mm256_hadd_ps(
                    _mm256_loadu_ps(r[2].as_ptr()),
                    _mm256_loadu_ps(r[3].as_ptr()),
                );
                let hh = _mm256_hadd_ps(h01, h23);
                let s = _mm_add_ps(_mm256_castps256_ps128(hh), _mm256_extractf128_ps::<1>(hh));
                _mm_storeu_ps(y.as_mut_ptr(), s);
            }
        }
        for (y, a) in outs.into_remainder().iter_mut().zip(quads.remainder()) {
            *y = super::lane_sum(a);
        }
    }

    /// Most groups interleaved by the AVX2 kernel (4 × 8 = 32 modes in flight).
    const G_AVX: usize = 4;
    /// Groups interleaved by the SSE2 kernel (2 × 8 = 16 modes in flight).
    const G_SSE: usize = 2;

    pub(super) fn avx2_fma<const ST: bool, const PH: bool>(
        m: &mut Modes<'_>,
        x: &[f32],
        acc: &mut Acc,
        side: &mut Acc,
    ) {
        assert!(super::Kernel::Avx2Fma.is_available());
        let groups = m.c.len() / LANES;
        let mut k = 0;
        while k < groups {
            // As many groups in flight as remain, up to G_AVX: a short range (the object's
            // high band is three groups) still hides the recursion's latency. The order in
            // which groups add into the accumulator is the same whatever the grouping.
            let step = (groups - k).min(G_AVX);
            // SAFETY: the CPU has AVX2 and FMA (asserted above, `is_x86_feature_detected!`),
            // which is the only requirement of these `target_feature` functions beyond the
            // bounds they check themselves.
            unsafe {
                match step {
                    4 => avx2_groups::<4, ST, PH>(m, k * LANES, x, acc, side),
                    3 => avx2_groups::<3, ST, PH>(m, k * LANES, x, acc, side),
                    2 => avx2_groups::<2, ST, PH>(m, k * LANES, x, acc, side),
                    _ => avx2_groups::<1, ST, PH>(m, k * LANES, x, acc, side),
                }
            }
            k += step;
        }
    }

    pub(super) fn sse2<const ST: bool, const PH: bool>(
        m: &mut Modes<'_>,
        x: &[f32],
        acc: &mut Acc,
        side: &mut Acc,
    ) {
        let groups = m.c.len() / LANES;
        let mut k = 0;
        while k < groups {
            if groups - k >= G_SSE {
                sse2_groups::<G_SSE, ST, PH>(m, k * LANES, x, acc, side);
                k += G_SSE;
            } else {
                sse2_groups::<1, ST, PH>(m, k * LANES, x, acc, side);
                k += 1;
            }
        }
    }

    /// `G` groups starting at mode `o`, AVX2 + FMA: per sample
    /// `re ← c·re + (g·x − s·im)`, `im ← s·re + c·im` (fused; `PH`:
    /// `im ← s·re + (c·im + h·x)`), `acc[t] += im` and, stereo, `side[t] += d·im` (fused).
    ///
    /// # Safety
    /// The CPU must support AVX2 and FMA.
    #[target_feature(enable = "avx2,fma")]
    #[allow(unused_unsafe)] // value intrinsics are safe here from Rust 1.87; MSRV is 1.85
    unsafe fn avx2_groups<const G: usize, const ST: bool, const PH: bool>(
        m: &mut Modes<'_>,
        o: usize,
        x: &[f32],
        acc: &mut Acc,
        side: &mut Acc,
    ) {
        assert!(o + G * LANES <= m.c.len() && m.re.len() == m.c.len());
        assert!(m.im.len() == m.c.len() && m.s.len() == m.c.len() && m.g.len() == m.c.len());
        assert!(m.d.len() == m.c.len() && m.h.len() == m.c.len());
        assert!(x.len() <= BLOCK);
        // SAFETY: every pointer below addresses `o + k·LANES .. o + (k+1)·LANES` with
        // k < G, inside the seven arrays (asserted above), or row t < x.len() ≤ BLOCK of
        // `acc`, whose rows are 32 bytes and 32-byte aligned (`Acc` is `align(32)`), as the
        // aligned load/store require. The state is written through pointers taken from
        // `Modes`' exclusive slices, which nothing else touches meanwhile.
        unsafe {
            let (pre, pim) = (m.re.as_mut_ptr(), m.im.as_mut_ptr());
            let mut re = [_mm256_setzero_ps(); G];
            let mut im = [_mm256_setzero_ps(); G];
            let mut c = [_mm256_setzero_ps(); G];
            let mut s = [_mm256_setzero_ps(); G];
            let mut g = [_mm256_setzero_ps(); G];
            let mut d = [_mm256_setzero_ps(); G];
            let mut h = [_mm256_setzero_ps(); G];
            for k in 0..G {
                let p = o + k * LANES;
                re[k] = _mm256_loadu_ps(pre.add(p));
                im[k] = _mm256_loadu_ps(pim.add(p));
                c[k] = _mm256_loadu_ps(m.c.as_ptr().add(p));
                s[k] = _mm256_loadu_ps(m.s.as_ptr().add(p));
                g[k] = _mm256_loadu_ps(m.g.as_ptr().add(p));
                if ST {
                    d[k] = _mm256_loadu_ps(m.d.as_ptr().add(p));
                }
                if PH {
                    h[k] = _mm256_loadu_ps(m.h.as_ptr().add(p));
                }
            }
            let pacc = acc.0.as_mut_ptr() as *mut f32;
            let pside = side.0.as_mut_ptr() as *mut f32;
            for (t, &xt) in x.iter().enumerate() {
                let xv = _mm256_set1_ps(xt);
                let row = pacc.add(t * LANES);
                let row_side = pside.add(t * LANES);
                let mut a = _mm256_load_ps(row);
                let mut b = if ST {
                    _mm256_load_ps(row_side)
                } else {
                    _mm256_setzero_ps()
                };
                for k in 0..G {
                    let gx = _mm256_mul_ps(g[k], xv);
                    let nr = _mm256_fmadd_ps(c[k], re[k], _mm256_fnmadd_ps(s[k], im[k], gx));
                    let ni = if PH {
                        let ci = _mm256_fmadd_ps(c[k], im[k], _mm256_mul_ps(h[k], xv));
                        _mm256_fmadd_ps(s[k], re[k], ci)
                    } else {
                        _mm256_fmadd_ps(s[k], re[k], _mm256_mul_ps(c[k], im[k]))
                    };
                    re[k] = nr;
                    im[k] = ni;
                    a = _mm256_add_ps(a, ni);
                    if ST {
                        b = _mm256_fmadd_ps(d[k], ni, b);
                    }
                }
                _mm256_store_ps(row, a);
                if ST {
                    _mm256_store_ps(row_side, b);
                }
            }
            for k in 0..G {
                let p = o + k * LANES;
                _mm256_storeu_ps(pre.add(p), re[k]);
                _mm256_storeu_ps(pim.add(p), im[k]);
            }
        }
    }

    /// `G` groups starting at mode `o`, SSE2 (two 4-lane halves per group): per sample
    /// `re ← (c·re − s·im) + g·x`, `im ← s·re + c·im` (`PH`: `+ h·x`), `acc[t] += im` and,
    /// stereo, `side[t] += d·im`, rounded exactly as the scalar kernel rounds.
    #[allow(unused_unsafe)] // value intrinsics are safe here from Rust 1.87; MSRV is 1.85
    fn sse2_groups<const G: usize, const ST: bool, const PH: bool>(
        m: &mut Modes<'_>,
        o: usize,
        x: &[f32],
        acc: &mut Acc,
        side: &mut Acc,
    ) {
        assert!(o + G * LANES <= m.c.len() && m.re.len() == m.c.len());
        assert!(m.im.len() == m.c.len() && m.s.len() == m.c.len() && m.g.len() == m.c.len());
        assert!(m.d.len() == m.c.len() && m.h.len() == m.c.len());
        assert!(x.len() <= BLOCK);
        // SAFETY: SSE2 is part of the x86-64 baseline. Every pointer addresses
        // `o + k·LANES + h·4 .. +4` with k < G, h < 2, inside the seven arrays (asserted
        // above), or half h of row t < x.len() ≤ BLOCK of `acc` (16-byte aligned: rows are
        // 32-byte aligned). The state is written through pointers taken from `Modes`' exclusive
        // slices, which nothing else touches meanwhile.
        unsafe {
            let (pre, pim) = (m.re.as_mut_ptr(), m.im.as_mut_ptr());
            let z = _mm_setzero_ps();
            let (mut re, mut im) = ([[z; 2]; G], [[z; 2]; G]);
            let (mut c, mut s, mut g) = ([[z; 2]; G], [[z; 2]; G], [[z; 2]; G]);
            let (mut d, mut hg) = ([[z; 2]; G], [[z; 2]; G]);
            for k in 0..G {
                for h in 0..2 {
                    let p = o + k * LANES + 4 * h;
                    if PH {
                        hg[k][h] = _mm_loadu_ps(m.h.as_ptr().add(p));
                    }
                    re[k][h] = _mm_loadu_ps(pre.add(p));
                    im[k][h] = _mm_loadu_ps(pim.add(p));
                    c[k][h] = _mm_loadu_ps(m.c.as_ptr().add(p));
                    s[k][h] = _mm_loadu_ps(m.s.as_ptr().add(p));
                    g[k][h] = _mm_loadu_ps(m.g.as_ptr().add(p));
                    d[k][h] = _mm_loadu_ps(m.d.as_ptr().add(p));
                }
            }
            let pacc = acc.0.as_mut_ptr() as *mut f32;
            let pside = side.0.as_mut_ptr() as *mut f32;
            for (t, &xt) in x.iter().enumerate() {
                let xv = _mm_set1_ps(xt);
                for h in 0..2 {
                    let row = pacc.add(t * LANES + 4 * h);
                    let row_side = pside.add(t * LANES + 4 * h);
                    let mut a = _mm_load_ps(row);
                    let mut b = if ST { _mm_load_ps(row_side) } else { z };
                    for k in 0..G {
                        let cr = _mm_mul_ps(c[k][h], re[k][h]);
                        let si = _mm_mul_ps(s[k][h], im[k][h]);
                        let gx = _mm_mul_ps(g[k][h], xv);
                        let nr = _mm_add_ps(_mm_sub_ps(cr, si), gx);
                        let sr = _mm_mul_ps(s[k][h], re[k][h]);
                        let ci = _mm_mul_ps(c[k][h], im[k][h]);
                        let ni = if PH {
                            _mm_add_ps(_mm_add_ps(sr, ci), _mm_mul_ps(hg[k][h], xv))
                        } else {
                            _mm_add_ps(sr, ci)
                        };
                        re[k][h] = nr;
                        im[k][h] = ni;
                        a = _mm_add_ps(a, ni);
                        if ST {
                            b = _mm_add_ps(b, _mm_mul_ps(d[k][h], ni));
                        }
                    }
                    _mm_store_ps(row, a);
                    if ST {
                        _mm_store_ps(row_side, b);
                    }
                }
            }
            for k in 0..G {
                for h in 0..2 {
                    let p = o + k * LANES + 4 * h;
                    _mm_storeu_ps(pre.add(p), re[k][h]);
                    _mm_storeu_ps(pim.add(p), im[k][h]);
                }
            }
        }
    }
}
