//! Real strikes, resynthesized (issue #26): every strike of the corpus
//! (`trundle_test_support::strike_corpus`: GM SoundFont percussion and pitched percussion,
//! drum-kit wood block, cowbell and tom) is fitted with `trundle fit-object`, struck once with
//! `trundle render --object FIT --impulse`, and judged against its recording
//! (`trundle_test_support::strike_judge`: median |cents| of the 12 strongest peaks ≤ 10,
//! median narrow-band T60 ratio 0.67–1.5, RMS third-octave difference of the first 0.5 s
//! ≤ 6 dB). The test prints the table the README shows:
//!
//! ```sh
//! cargo test -p trundle-cli --test strikes -- --ignored --nocapture
//! ```

use trundle_test_support::scratch::scratch;
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
    let failed: Vec<_> = rows.iter().filter(|r| !r.pass()).map(|r| r.name).collect();
    assert!(failed.is_empty(), "outside the limits: {failed:?}\n{t}");
}
