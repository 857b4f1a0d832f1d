//! Analysis: reading signals back — impacts in a force and the ARMA(1,1) fit of their series
//! ([`impacts`]), the one Toeplitz/Levinson–Durbin solver ([`toeplitz`]), the one definition
//! of third-octave bands and their energy ([`third_octave`]) and, with the feature `fit`, the
//! one short-time Fourier transform (`stft`). Depends only on [`crate::block`]: the object
//! (a fitted object's spectrum) and the fitting read it; it reads nothing of the model.

#[cfg(feature = "fit")]
pub mod compare;
pub mod impacts;
#[cfg(feature = "fit")]
pub mod stft;
pub mod third_octave;
pub mod toeplitz;
