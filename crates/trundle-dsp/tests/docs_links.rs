//! Every relative link in README.md and docs/**/*.md resolves: the file (or folder) exists, and
//! for `#anchor` links the target page has a heading with that GitHub-style slug. Links to
//! other sites (`https:`, `mailto:` …) are not followed. Reads files only: no dependencies,
//! well under a second.

use std::collections::HashMap;
use std::path::PathBuf;

use trundle_test_support::tree::workspace_root as root;

fn pages() -> Vec<PathBuf> {
    trundle_test_support::tree::doc_pages()
}

/// The page's lines outside fenced code blocks (```` ``` ```` or `~~~`).
fn prose_lines(text: &str) -> Vec<&str> {
    let mut fence: Option<&str> = None;
    let mut out = Vec::new();
    for line in text.lines() {
        let t = line.trim_start();
        match fence {
            Some(f) if t.starts_with(f) => fence = None,
            Some(_) => {}
            None if t.starts_with("```") => fence = Some("```"),
            None if t.starts_with("~~~") => fence = Some("~~~"),
            None => out.push(line),
        }
    }
    out
}

/// A line with its inline code spans (`` `…` ``) blanked, so code is never read as a link.
fn without_code_spans(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut in_code = false;
    for c in line.chars() {
        if c == '`' {
            in_code = !in_code;
            out.push(' ');
        } else {
            out.push(if in_code { ' ' } else { c });
        }
    }
    out
}

/// The link targets on a page: inline links and images `[text](target)`, `![alt](target)`,
/// and reference definitions `[label]: target`.
fn link_targets(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in prose_lines(text) {
        let line = without_code_spans(line);
        let trimmed = line.trim_start();
        if trimmed.starts_with('[') {
            if let Some(pos) = trimmed.find("]:") {
                let target = trimmed[pos + 2..].split_whitespace().next().unwrap_or("");
                out.push(target.trim_matches(['<', '>']).to_owned());
                continue;
            }
        }
        let mut rest = line.as_str();
        while let Some(pos) = rest.find("](") {
            let after = &rest[pos + 2..];
            // The target ends at the parenthesis that closes the one opened by "](".
            let mut depth = 1;
            let mut end = after.len();
            for (i, c) in after.char_indices() {
                match c {
                    '(' => depth += 1,
                    ')' => {
                        depth -= 1;
                        if depth == 0 {
                            end = i;
                            break;
                        }
                    }
                    _ => {}
                }
            }
            // An optional title: `(target "title")`.
            let target = after[..end].split_whitespace().next().unwrap_or("");
            out.push(target.trim_matches(['<', '>']).to_owned());
            rest = &after[end.min(after.len())..];
        }
    }
    out
}

/// GitHub's anchor for a heading: lower case, markup and punctuation dropped (letters,
/// digits, `_` and `-` kept), spaces to `-`.
fn slug(heading: &str) -> String {
    // A link in a heading anchors by its text: "[text](url)" → "text".
    let mut text = String::new();
    let mut rest = heading;
    while let Some(open) = rest.find('[') {
        match rest[open..].find("](") {
            Some(mid) => {
                let close = rest[open + mid..].find(')').map(|c| open + mid + c);
                text.push_str(&rest[..open]);
                text.push_str(&rest[open + 1..open + mid]);
                rest = close.map_or("", |c| &rest[c + 1..]);
            }
            None => break,
        }
    }
    text.push_str(rest);
    text.trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            '-' | '_' => Some(c),
            c if c.is_alphanumeric() => Some(c),
            _ => None,
        })
        .collect()
}

/// The anchors of a page's headings, with GitHub's `-1`, `-2` … for repeated ones.
fn anchors(text: &str) -> Vec<String> {
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut out = Vec::new();
    for line in prose_lines(text) {
        let level = line.chars().take_while(|&c| c == '#').count();
        if !(1..=6).contains(&level) || !line[level..].starts_with(' ') {
            continue;
        }
        let heading = line[level..].trim().trim_end_matches('#').trim();
        let base = slug(heading);
        let n = seen.entry(base.clone()).or_insert(0);
        out.push(if *n == 0 {
            base.clone()
        } else {
            format!("{base}-{n}")
        });
        *n += 1;
    }
    out
}

/// Whether a target leaves the repository (a URL scheme such as `https:` or `mailto:`).
fn is_external(target: &str) -> bool {
    match target.find(':') {
        Some(i) => {
            let scheme = &target[..i];
            !scheme.is_empty()
                && !scheme.contains(['/', '#', '.'])
                && scheme
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || "+-".contains(c))
        }
        None => target.starts_with("//"),
    }
}

#[test]
fn every_relative_link_in_the_docs_resolves() {
    let mut checked = 0;
    let mut broken = Vec::new();
    let pages = pages();
    assert!(
        pages.iter().any(|p| p.ends_with("docs/guide/SUMMARY.md")),
        "docs/guide/SUMMARY.md is missing"
    );
    for page in &pages {
        let text = std::fs::read_to_string(page).expect("a readable page");
        let name = page
            .strip_prefix(root())
            .unwrap_or(page)
            .display()
            .to_string();
        for target in link_targets(&text) {
            if target.is_empty() {
                broken.push(format!("{name}: an empty link target"));
                continue;
            }
            if is_external(&target) {
                continue;
            }
            checked += 1;
            let (path, anchor) = match target.split_once('#') {
                Some((p, a)) => (p, Some(a)),
                None => (target.as_str(), None),
            };
            let file = if path.is_empty() {
                page.clone()
            } else {
                page.parent().expect("a page's folder").join(path)
            };
            if !file.exists() {
                broken.push(format!("{name}: {target}: no such file"));
                continue;
            }
            let Some(anchor) = anchor else { continue };
            if file.extension().is_none_or(|x| x != "md") {
                broken.push(format!(
                    "{name}: {target}: an anchor into a file that is not Markdown"
                ));
                continue;
            }
            let target_text = std::fs::read_to_string(&file).expect("a readable target");
            if !anchors(&target_text).iter().any(|a| a == anchor) {
                broken.push(format!("{name}: {target}: no heading with that anchor"));
            }
        }
    }
    println!("{checked} relative links checked in {} pages", pages.len());
    assert!(
        broken.is_empty(),
        "broken links:\n  {}",
        broken.join("\n  ")
    );
    assert!(checked > 0, "no links found: the parser is broken");
}

#[test]
fn slugs_follow_github() {
    assert_eq!(slug("A thousand balls: crowds"), "a-thousand-balls-crowds");
    assert_eq!(
        slug("A recorded prop: Load object…"),
        "a-recorded-prop-load-object"
    );
    assert_eq!(slug("The `trundle` command"), "the-trundle-command");
    assert_eq!(
        slug("Rub, scratch, roll — and where the ball is"),
        "rub-scratch-roll--and-where-the-ball-is"
    );
    assert_eq!(
        slug("§11 Gestures and surfaces"),
        "11-gestures-and-surfaces"
    );
    assert_eq!(slug("The `crowd_detail` knob"), "the-crowd_detail-knob");
    assert_eq!(slug("See [MODEL.md](MODEL.md) first"), "see-modelmd-first");
    assert_eq!(
        anchors("# A\n## A\n```\n# A\n```\n# A\n"),
        ["a", "a-1", "a-2"]
    );
}

#[test]
fn links_are_read_outside_code_only() {
    let text = "a [x](one.md) and `[y](two.md)`\n```\n[z](three.md)\n```\n![p](../p.png \"t\")\n[r]: <four.md#h>\n";
    assert_eq!(link_targets(text), ["one.md", "../p.png", "four.md#h"]);
    assert!(is_external("https://example.org/a.md"));
    assert!(is_external("mailto:a@b.c"));
    assert!(!is_external("guide/sound.md#the-contact-ball-materials"));
    assert!(!is_external("#anchor"));
}

#[test]
fn code_cites_guide_pages_not_readme_sections() {
    // The README is a newcomer's page; the manual's sections live in docs/guide/. A comment
    // that sends a reader to a README section by name points at nothing.
    let needle = ["README", " \""].concat();
    let mut stale = Vec::new();
    for file in trundle_test_support::tree::workspace_rust_files() {
        let text = std::fs::read_to_string(&file).expect("a readable source file");
        for (i, line) in text.lines().enumerate() {
            if line.contains(&needle) {
                let name = file
                    .strip_prefix(root())
                    .unwrap_or(&file)
                    .display()
                    .to_string();
                stale.push(format!("{name}:{}: {}", i + 1, line.trim()));
            }
        }
    }
    assert!(
        stale.is_empty(),
        "cite the guide page (docs/guide/…) instead:\n  {}",
        stale.join("\n  ")
    );
}
