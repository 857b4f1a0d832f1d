//! The README's parameter table names every parameter of the one table (so the docs a
//! newcomer reads cannot fall behind the code).

#[test]
fn readme_lists_every_parameter_id() {
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md"))
        .expect("README.md at the workspace root");
    let missing: Vec<&str> = trundle_dsp::PARAMS
        .iter()
        .map(|p| p.key)
        .filter(|k| !readme.contains(&format!("`{k}`")))
        .collect();
    assert!(
        missing.is_empty(),
        "README.md does not document: {missing:?}"
    );
}
