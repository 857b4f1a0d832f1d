//! User presets: files the editor saves, loads, renames, tags and deletes in a directory of
//! the user's own, in the same versioned JSON as the built-in `presets/*.json`
//! ([`Preset::to_json`] / [`Preset::from_json`]).
//!
//! * **Where.** [`PresetStore::default_dir`]: `$TRUNDLE_PRESET_DIR` when set (tests, or a
//!   user who keeps presets elsewhere), otherwise `presets/` in the platform's user data
//!   directory (`directories`: `~/.local/share/trundle/presets` on Linux,
//!   `~/Library/Application Support/Trundle/presets` on macOS,
//!   `%APPDATA%\Trundle\data\presets` on Windows). Every operation takes the store's
//!   directory, so tests use a directory of their own.
//! * **Files.** One `<slug>.json` per preset, the slug made from the name (`My Glass
//!   Roll` → `my-glass-roll.json`); the name itself is the file's `name` field. Writes go
//!   to a temporary file that is then renamed over the target, so a crash never leaves half
//!   a preset.
//! * **Tags.** The preset format refuses unknown keys (a preset is never loaded
//!   half-right), so tags do not go into the preset files: they live in a sidecar index,
//!   [`TAGS_FILE`], in the same directory (`{"trundle_preset_tags": 1, "tags": {"file.json":
//!   ["tag", …]}}`). A missing index means no tags; an unreadable one is reported and
//!   treated as empty (the next tag edit rewrites it).
//! * **Errors.** Files are read by the command's reader ([`trundle_io::preset_file`]: the
//!   same size cap and messages). A file that does not parse is listed with the reason
//!   ([`UserPreset::preset`] is `Err`), never skipped silently and never a panic.
//! * **Threads.** This is file I/O: the editor calls it on the GUI thread only, on a user's
//!   action (opening the browser, save, rename, delete, tag), never from `process`.

use serde_json::{Map, Value};
use std::collections::BTreeMap;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use trundle_dsp::object::fitted::ObjectFile;
use trundle_dsp::scene::body_eq::BodyEqCurve;
use trundle_dsp::scene::preset::Preset;
use trundle_dsp::Params;
use trundle_io::preset_file::read_preset_file;

/// The environment variable that overrides the user preset directory.
pub const DIR_ENV: &str = "TRUNDLE_PRESET_DIR";

/// The sidecar file holding the user presets' tags (not a preset: listing skips it).
pub const TAGS_FILE: &str = ".trundle-tags.json";

/// The tag index's format version.
const TAGS_VERSION: u64 = 1;

/// One file of the user preset directory.
#[derive(Clone, Debug, PartialEq)]
pub struct UserPreset {
    /// The file name (`my-glass-roll.json`): the preset's identity in the store.
    pub file: String,
    /// The parsed preset, or why the file cannot be loaded.
    pub preset: Result<Preset, String>,
    /// The preset's tags (from the sidecar index), sorted, without duplicates.
    pub tags: Vec<String>,
}

impl UserPreset {
    /// The name to show: the preset's own, or the file name of an unloadable file.
    pub fn display_name(&self) -> &str {
        match &self.preset {
            Ok(p) => &p.name,
            Err(_) => &self.file,
        }
    }
}

/// What listing the directory found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Listing {
    /// The presets, sorted by display name (case-insensitive).
    pub presets: Vec<UserPreset>,
    /// A problem with the directory or the tag index (the listing is still usable).
    pub warning: Option<String>,
}

/// A directory of user presets.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PresetStore {
    dir: PathBuf,
}

impl PresetStore {
    /// A store in `dir` (created on the first save).
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        Self { dir: dir.into() }
    }

    /// The default directory: `$TRUNDLE_PRESET_DIR`, else `presets` in the platform's user
    /// data directory; `None` if the platform has no home directory.
    pub fn default_dir() -> Option<PathBuf> {
        if let Some(dir) = std::env::var_os(DIR_ENV).filter(|d| !d.is_empty()) {
            return Some(PathBuf::from(dir));
        }
        directories::ProjectDirs::from("", "", "Trundle").map(|d| d.data_dir().join("presets"))
    }

    /// The store's directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Every `*.json` file of the directory (but the tag index) with its parse result and
    /// tags. A directory that does not exist yet is an empty listing.
    pub fn list(&self) -> Listing {
        let mut listing = Listing::default();
        let entries = match fs::read_dir(&self.dir) {
            Ok(e) => e,
            Err(e) if e.kind() == io::ErrorKind::NotFound => return listing,
            Err(e) => {
                listing.warning = Some(format!("cannot read {}: {e}", self.dir.display()));
                return listing;
            }
        };
        let (tags, warning) = match self.read_tags() {
            Ok(t) => (t, None),
            Err(e) => (BTreeMap::new(), Some(e)),
        };
        listing.warning = warning;
        for entry in entries.flatten() {
            let file = entry.file_name().to_string_lossy().into_owned();
            if file == TAGS_FILE || !file.ends_with(".json") || file.starts_with('.') {
                continue;
            }
            let preset = read_preset_file(&entry.path()).map_err(|e| e.problem.to_string());
            let tags = tags.get(&file).cloned().unwrap_or_default();
            listing.presets.push(UserPreset { file, preset, tags });
        }
        listing.presets.sort_by(|a, b| {
            let key = |p: &UserPreset| p.display_name().to_lowercase();
            key(a).cmp(&key(b)).then_with(|| a.file.cmp(&b.file))
        });
        listing
    }

    /// Load one preset by file name (the command's reader: at most
    /// [`trundle_io::preset_file::MAX_PRESET_BYTES`]).
    pub fn load(&self, file: &str) -> Result<Preset, String> {
        read_preset_file(&self.path(file)?).map_err(|e| format!("{file}: {}", e.problem))
    }

    /// Save `params` as a preset named `name` with `description` and `tags`, with the fitted
    /// object and the body EQ curve played (if any); returns its file name. A preset of the same name (the same file) is replaced.
    pub fn save(
        &self,
        name: &str,
        description: &str,
        params: &Params,
        object: Option<ObjectFile>,
        body_eq: Option<Arc<BodyEqCurve>>,
        tags: &[String],
    ) -> Result<String, String> {
        let name = name.trim();
        let file = file_name_for(name)?;
        let preset = Preset {
            name: name.to_string(),
            description: description.to_string(),
            params: *params,
            automation: Vec::new(),
            balls: Vec::new(),
            object,
            body_eq,
            take: None,
            matched: None,
        };
        fs::create_dir_all(&self.dir)
            .map_err(|e| format!("cannot create {}: {e}", self.dir.display()))?;
        self.write_atomic(&file, &preset.to_json())?;
        self.set_tags(&file, tags)?;
        Ok(file)
    }

    /// Rename the preset in `file` to `new_name` (its `name` field and its file, which
    /// follows the new name; its tags follow it). Refuses a name whose file already holds
    /// another preset. Returns the new file name.
    pub fn rename(&self, file: &str, new_name: &str) -> Result<String, String> {
        let mut preset = self.load(file)?;
        let new_name = new_name.trim();
        let new_file = file_name_for(new_name)?;
        if new_file != file && self.path(&new_file)?.exists() {
            return Err(format!("a preset file {new_file} already exists"));
        }
        preset.name = new_name.to_string();
        self.write_atomic(&new_file, &preset.to_json())?;
        if new_file != file {
            fs::remove_file(self.path(file)?).map_err(|e| format!("{file}: {e}"))?;
            let mut tags = self.read_tags().unwrap_or_default();
            if let Some(t) = tags.remove(file) {
                tags.insert(new_file.clone(), t);
            }
            self.write_tags(&tags)?;
        }
        Ok(new_file)
    }

    /// Delete the preset in `file` (and its tags).
    pub fn delete(&self, file: &str) -> Result<(), String> {
        fs::remove_file(self.path(file)?).map_err(|e| format!("{file}: {e}"))?;
        let mut tags = self.read_tags().unwrap_or_default();
        if tags.remove(file).is_some() {
            self.write_tags(&tags)?;
        }
        Ok(())
    }

    /// Replace the tags of the preset in `file` (cleaned: trimmed, lower-case, sorted,
    /// without empty ones or duplicates).
    pub fn set_tags(&self, file: &str, tags: &[String]) -> Result<(), String> {
        let mut index = self.read_tags().unwrap_or_default();
        let clean = clean_tags(tags.iter().map(String::as_str));
        if clean.is_empty() {
            if index.remove(file).is_none() {
                return Ok(());
            }
        } else {
            index.insert(file.to_string(), clean);
        }
        self.write_tags(&index)
    }

    /// The path of `file` in the directory, refusing names that would leave it.
    fn path(&self, file: &str) -> Result<PathBuf, String> {
        if file.is_empty() || file.contains(['/', '\\']) || file.starts_with('.') {
            return Err(format!("'{file}' is not a preset file name"));
        }
        Ok(self.dir.join(file))
    }

    fn write_atomic(&self, file: &str, text: &str) -> Result<(), String> {
        let target = self.dir.join(file);
        let tmp = self.dir.join(format!(".{file}.tmp"));
        fs::write(&tmp, text)
            .and_then(|()| fs::rename(&tmp, &target))
            .map_err(|e| {
                let _ = fs::remove_file(&tmp);
                format!("cannot write {}: {e}", target.display())
            })
    }

    /// The tag index (empty if there is none), or why it cannot be read.
    fn read_tags(&self) -> Result<BTreeMap<String, Vec<String>>, String> {
        let text = match fs::read_to_string(self.dir.join(TAGS_FILE)) {
            Ok(t) => t,
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(BTreeMap::new()),
            Err(e) => return Err(format!("tag index {TAGS_FILE}: {e}")),
        };
        let bad = |why: &str| format!("tag index {TAGS_FILE} ignored: {why}");
        let value: Value = serde_json::from_str(&text).map_err(|e| bad(&e.to_string()))?;
        let version = value.get("trundle_preset_tags").and_then(Value::as_u64);
        if version != Some(TAGS_VERSION) {
            return Err(bad("not a version 1 tag index"));
        }
        let map = value
            .get("tags")
            .and_then(Value::as_object)
            .ok_or_else(|| bad("no 'tags' object"))?;
        let mut out = BTreeMap::new();
        for (file, list) in map {
            let list = list
                .as_array()
                .ok_or_else(|| bad(&format!("the tags of {file} are not a list")))?;
            let tags = clean_tags(list.iter().filter_map(Value::as_str));
            if !tags.is_empty() {
                out.insert(file.clone(), tags);
            }
        }
        Ok(out)
    }

    fn write_tags(&self, index: &BTreeMap<String, Vec<String>>) -> Result<(), String> {
        let mut tags = Map::new();
        for (file, list) in index {
            tags.insert(
                file.clone(),
                Value::Array(list.iter().cloned().map(Value::String).collect()),
            );
        }
        let mut top = Map::new();
        top.insert("trundle_preset_tags".into(), Value::from(TAGS_VERSION));
        top.insert("tags".into(), Value::Object(tags));
        let text = serde_json::to_string_pretty(&Value::Object(top))
            .expect("a JSON value always serializes");
        fs::create_dir_all(&self.dir)
            .map_err(|e| format!("cannot create {}: {e}", self.dir.display()))?;
        self.write_atomic(TAGS_FILE, &text)
    }
}

/// The file name a preset called `name` is saved under: its words in lower case joined by
/// `-` (letters and digits of any script kept, everything else a separator) + `.json`.
pub fn file_name_for(name: &str) -> Result<String, String> {
    let mut slug = String::new();
    for word in name
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
    {
        if !slug.is_empty() {
            slug.push('-');
        }
        slug.extend(word.chars().flat_map(char::to_lowercase));
    }
    if slug.is_empty() {
        return Err("a preset needs a name with a letter or a digit".into());
    }
    // Keep file names short enough for every file system (bytes, on a char boundary).
    if slug.len() > 80 {
        let mut end = 80;
        while !slug.is_char_boundary(end) {
            end -= 1;
        }
        slug.truncate(end);
    }
    Ok(format!("{slug}.json"))
}

/// Tags as typed (`"wood, Dark  loop"` → `["dark", "loop", "wood"]`): split on commas and
/// white space, lower case, sorted, no duplicates.
pub fn parse_tags(text: &str) -> Vec<String> {
    clean_tags(text.split([',', ' ', '\t', '\n']))
}

fn clean_tags<'a>(tags: impl Iterator<Item = &'a str>) -> Vec<String> {
    let mut out: Vec<String> = tags
        .map(|t| t.trim().to_lowercase())
        .filter(|t| !t.is_empty())
        .collect();
    out.sort();
    out.dedup();
    out
}

/// Whether a preset called `name` with `tags` passes the browser's filter: `text` is found
/// in the name (case-insensitive; empty matches all) and, if `tag` is given, the preset has
/// it.
pub fn matches_filter(name: &str, tags: &[String], text: &str, tag: Option<&str>) -> bool {
    let text = text.trim().to_lowercase();
    (text.is_empty() || name.to_lowercase().contains(&text))
        && tag.is_none_or(|t| tags.iter().any(|x| x == t))
}

#[cfg(test)]
mod tests {
    use super::*;
    use trundle_dsp::ParamId;

    /// A fresh, empty directory for one test.
    fn scratch(name: &str) -> PresetStore {
        let dir = std::env::temp_dir().join(format!(
            "trundle-user-presets-{}-{name}",
            std::process::id()
        ));
        let _ = fs::remove_dir_all(&dir);
        PresetStore::new(dir)
    }

    fn some_params() -> Params {
        let mut p = Params::default();
        p.set(ParamId::Velocity, 0.73).unwrap();
        p.set(ParamId::ObjectSize, 0.25).unwrap();
        p.set(ParamId::Shape, 3.0).unwrap();
        p.set(ParamId::Seed, 12_345.0).unwrap();
        p.set(ParamId::GainDb, -7.5).unwrap();
        p
    }

    #[test]
    fn save_list_load_round_trips_every_parameter() {
        let store = scratch("round-trip");
        let params = some_params();
        let tags = vec!["Glass".to_string(), "loop".to_string()];
        let file = store
            .save("My Glass Roll", "a test", &params, None, None, &tags)
            .unwrap();
        assert_eq!(file, "my-glass-roll.json");
        let listing = store.list();
        assert_eq!(listing.warning, None);
        assert_eq!(listing.presets.len(), 1, "the tag index is not a preset");
        let entry = &listing.presets[0];
        assert_eq!(entry.file, file);
        assert_eq!(entry.tags, vec!["glass", "loop"]);
        let listed = entry.preset.as_ref().unwrap();
        assert_eq!(listed.name, "My Glass Roll");
        assert_eq!(listed.description, "a test");
        let loaded = store.load(&file).unwrap();
        for (spec, v) in params.iter() {
            assert_eq!(loaded.params.get(spec.id), v, "{}", spec.key);
        }
        assert_eq!(loaded.params, params);
        // Saving under the same name replaces it.
        store
            .save("my glass roll", "", &Params::default(), None, None, &[])
            .unwrap();
        let listing = store.list();
        assert_eq!(listing.presets.len(), 1);
        assert_eq!(listing.presets[0].tags, Vec::<String>::new());
        let _ = fs::remove_dir_all(store.dir());
    }

    #[test]
    fn rename_moves_the_file_and_its_tags() {
        let store = scratch("rename");
        let params = some_params();
        let file = store
            .save("Old", "", &params, None, None, &["dark".to_string()])
            .unwrap();
        let new_file = store.rename(&file, "Brand new").unwrap();
        assert_eq!(new_file, "brand-new.json");
        let listing = store.list();
        assert_eq!(listing.presets.len(), 1);
        let entry = &listing.presets[0];
        assert_eq!(entry.file, new_file);
        assert_eq!(entry.display_name(), "Brand new");
        assert_eq!(entry.tags, vec!["dark"]);
        assert_eq!(entry.preset.as_ref().unwrap().params, params);
        assert!(store.load(&file).is_err());
        // Renaming onto another preset's file is refused and changes nothing.
        store
            .save("Other", "", &Params::default(), None, None, &[])
            .unwrap();
        assert!(store.rename(&new_file, "other").is_err());
        assert_eq!(store.list().presets.len(), 2);
        // A new spelling of the same name keeps the file.
        assert_eq!(store.rename(&new_file, "BRAND NEW").unwrap(), new_file);
        assert_eq!(store.load(&new_file).unwrap().name, "BRAND NEW");
        let _ = fs::remove_dir_all(store.dir());
    }

    #[test]
    fn delete_removes_the_file_and_its_tags() {
        let store = scratch("delete");
        let a = store
            .save("A", "", &Params::default(), None, None, &["x".to_string()])
            .unwrap();
        store
            .save("B", "", &Params::default(), None, None, &[])
            .unwrap();
        store.delete(&a).unwrap();
        let listing = store.list();
        assert_eq!(listing.presets.len(), 1);
        assert_eq!(listing.presets[0].display_name(), "B");
        assert!(store.read_tags().unwrap().is_empty());
        assert!(store.delete(&a).is_err(), "deleting twice is an error");
        assert!(store.delete("../escape.json").is_err());
        let _ = fs::remove_dir_all(store.dir());
    }

    #[test]
    fn tags_filter_the_listing() {
        let store = scratch("tags");
        let p = Params::default();
        store
            .save("Wood table", "", &p, None, None, &parse_tags("wood, table"))
            .unwrap();
        store
            .save("Glass bowl", "", &p, None, None, &parse_tags("Glass  bowl"))
            .unwrap();
        let metal = store.save("Metal tray", "", &p, None, None, &[]).unwrap();
        store.set_tags(&metal, &parse_tags("metal,table")).unwrap();
        let listing = store.list();
        let pick = |text: &str, tag: Option<&str>| -> Vec<String> {
            listing
                .presets
                .iter()
                .filter(|e| matches_filter(e.display_name(), &e.tags, text, tag))
                .map(|e| e.display_name().to_string())
                .collect()
        };
        assert_eq!(pick("", Some("table")), vec!["Metal tray", "Wood table"]);
        assert_eq!(pick("", Some("glass")), vec!["Glass bowl"]);
        assert_eq!(pick("TAB", None), vec!["Wood table"]);
        assert_eq!(pick("tray", Some("table")), vec!["Metal tray"]);
        assert_eq!(pick("tray", Some("wood")), Vec::<String>::new());
        assert_eq!(pick("", None).len(), 3);
        let _ = fs::remove_dir_all(store.dir());
    }

    #[test]
    fn corrupt_files_are_listed_with_the_reason() {
        let store = scratch("corrupt");
        store
            .save("Good", "", &Params::default(), None, None, &[])
            .unwrap();
        fs::write(store.dir().join("broken.json"), "{ not json").unwrap();
        fs::write(
            store.dir().join("future.json"),
            r#"{"trundle_preset": 99, "name": "From the future"}"#,
        )
        .unwrap();
        fs::write(
            store.dir().join("bad-value.json"),
            r#"{"trundle_preset": 1, "name": "Bad", "params": {"velocity": 7}}"#,
        )
        .unwrap();
        fs::write(store.dir().join("notes.txt"), "not a preset").unwrap();
        fs::write(store.dir().join(TAGS_FILE), "[1, 2").unwrap();
        let listing = store.list();
        assert_eq!(listing.presets.len(), 4, "{listing:?}");
        let reason = |file: &str| -> String {
            let e = listing.presets.iter().find(|e| e.file == file).unwrap();
            e.preset.clone().unwrap_err()
        };
        assert!(reason("broken.json").contains("not a valid preset"));
        assert!(reason("future.json").contains("newer"));
        assert!(reason("bad-value.json").contains("velocity"));
        assert!(listing.warning.unwrap().contains(TAGS_FILE));
        assert!(store.load("broken.json").is_err());
        // A tag edit rewrites the unreadable index.
        store.set_tags("good.json", &parse_tags("ok")).unwrap();
        let listing = store.list();
        assert_eq!(listing.warning, None);
        let good = listing
            .presets
            .iter()
            .find(|e| e.file == "good.json")
            .unwrap();
        assert_eq!(good.tags, vec!["ok"]);
        let _ = fs::remove_dir_all(store.dir());
    }

    #[test]
    fn file_names_come_from_the_name() {
        assert_eq!(
            file_name_for("My Glass Roll").unwrap(),
            "my-glass-roll.json"
        );
        assert_eq!(file_name_for("  a/b\\c..d ").unwrap(), "a-b-c-d.json");
        assert_eq!(
            file_name_for("Kugel Über Holz").unwrap(),
            "kugel-über-holz.json"
        );
        assert!(file_name_for(" -/. ").is_err());
        assert!(file_name_for(&"x".repeat(300)).unwrap().len() <= 85);
    }

    #[test]
    fn a_missing_directory_is_an_empty_listing() {
        let store = scratch("missing");
        assert_eq!(store.list(), Listing::default());
    }

    #[test]
    fn the_environment_overrides_the_directory() {
        // Only this test touches the variable.
        std::env::set_var(DIR_ENV, "/tmp/trundle-elsewhere");
        assert_eq!(
            PresetStore::default_dir(),
            Some(PathBuf::from("/tmp/trundle-elsewhere"))
        );
        std::env::remove_var(DIR_ENV);
        let dir = PresetStore::default_dir();
        assert!(dir.is_none_or(|d| d.ends_with("presets")));
    }
}
