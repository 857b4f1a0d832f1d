//! Real strikes, resynthesized (issue #26): every strike of the corpus
//! (`trundle_test_support::strike_corpus`: GM SoundFont percussion and pitched percussion,
//! drum-kit wood block, cowbell and tom) is fitted with `trundle fit-object`, struck once with
//! `trundle render --object FIT --impulse`, and judged against its recording
//! (`trundle_test_support::strike_judge`: median |cents| of the 12 strongest peaks ≤ 10,
//! median narrow-band T60 ratio 0.67–1.5, RMS third-octave difference of the first 0.5 s
//! ≤ 6 dB). Three strikes are known to fall outside ([`KNOWN_OUTSIDE`], with why); every
//! other must pass. The test prints the table the README shows:
//!
//! ```sh
//! cargo test -p trundle-cli --test strikes -- --ignored --nocapture
//! ```

use trundle_test_support::scratch::scratch;

/// Strikes known to fall outside the limits today, with why (measured 26 Nov 2026; the
/// README's table shows their numbers). Every other strike must pass; when one of these
/// comes inside, the test says so and it leaves this list.
const KNOWN_OUTSIDE: [(&str, &str); 3] = [
    (
        "xylophone",
        "third-octave spectrum 13.4 dB RMS off: the bands between its few strong modes",
    ),
    (
        "tom, low (kit)",
        "28 cents: a drum's pitch glides as its head relaxes; a mode's frequency does not",
    ),
    (
        "music box",
        "the fit explains nothing (residual +0.3 dB): refused without --keep-poor-fit",
    ),
];
use trundle_test_support::strike_corpus::{measure, table, CORPUS};

#[test]
#[ignore = "needs Debian's hydrogen-drumkits and fluid-soundfont-gm (apt-get install hydrogen-drumkits fluid-soundfont-gm)"]
fn every_corpus_strike_is_inside_the_three_limits() {
    let d = scratch("strikes");
    let rows: Vec<_> = CORPUS.iter().map(|s| measure(&d, s, &[])).collect();
    for r in &rows {
        println!("{}: {:?}", r.name, r.verdict);
    }
    let t = table(&rows);
    println!("{t}");
    let known = |name: &str| KNOWN_OUTSIDE.iter().any(|(k, _)| *k == name);
    for r in rows.iter().filter(|r| known(r.name) && r.pass()) {
        println!(
            "now inside the limits: {} (take it off KNOWN_OUTSIDE)",
            r.name
        );
    }
    let failed: Vec<_> = rows
        .iter()
        .filter(|r| !r.pass() && !known(r.name))
        .map(|r| r.name)
        .collect();
    assert!(failed.is_empty(), "outside the limits: {failed:?}\n{t}");
    let inside = rows.iter().filter(|r| r.pass()).count();
    assert!(
        inside >= CORPUS.len() - KNOWN_OUTSIDE.len(),
        "{inside} inside\n{t}"
    );
}
