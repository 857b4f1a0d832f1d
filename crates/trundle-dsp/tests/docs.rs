//! The guide's parameter table (`docs/guide/parameters.md`) names every parameter of the one
//! table, and nothing else (so the docs a user reads cannot fall behind the code).

/// The IDs in the first column of the page's tables: every `` `id` `` in a row's first cell.
fn documented_ids(page: &str) -> Vec<String> {
    page.lines()
        .filter_map(|l| l.strip_prefix('|'))
        .filter_map(|row| row.split('|').next())
        .flat_map(|cell| {
            cell.split('`')
                .skip(1)
                .step_by(2)
                .map(str::to_owned)
                .collect::<Vec<_>>()
        })
        .collect()
}

#[test]
fn guide_lists_every_parameter_id() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/guide/parameters.md"
    );
    let page = std::fs::read_to_string(path).expect("docs/guide/parameters.md in the workspace");
    let ids = documented_ids(&page);
    let missing: Vec<&str> = trundle_dsp::PARAMS
        .iter()
        .map(|p| p.key)
        .filter(|k| !ids.iter().any(|id| id == k))
        .collect();
    assert!(
        missing.is_empty(),
        "docs/guide/parameters.md's table does not document: {missing:?}"
    );
    let unknown: Vec<&String> = ids
        .iter()
        .filter(|id| !trundle_dsp::PARAMS.iter().any(|p| p.key == id.as_str()))
        .collect();
    assert!(
        unknown.is_empty(),
        "docs/guide/parameters.md's table names IDs the table does not have: {unknown:?}"
    );
}
