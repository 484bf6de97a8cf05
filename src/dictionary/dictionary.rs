//! A drive family's object dictionary: named objects and the device-control profile,
//! loaded from YAML (the built-in files are compiled into the binary) and checked as a
//! whole. Its only I/O is reading a dictionary file; it knows nothing of transports,
//! links or protocols beyond object addresses.

use super::address::{Address, AddressParser};
use super::bench_limits::BenchLimits;
use super::dictionary_error::DictionaryError;
use super::eds::{eds_objects, is_eds_path, EdsFile, EdsObjects, OnBuiltIn};
use super::family_id::family_id;
use super::file_entry::FileEntry;
use super::object_def::ObjectDef;
use super::pole_pairs::PolePairs;
use super::profile::Profile;
use super::reader::read;
use super::role::Role;
use super::unknown_object::UnknownObject;
use super::validate::validate;
use super::value_error::ValueError;
use crate::diag::{did_you_mean, read_source, Diagnostic, Diagnostics, Source, Span, YamlNode};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

#[derive(Debug, Clone)]
pub struct Dictionary {
    family: String,
    family_span: Span,
    title: String,
    objects: Vec<ObjectDef>,
    profile: Option<Profile>,
    /// The bench limits in force; applied again after every [`Self::extend`], so no
    /// dictionary added later can raise them.
    bench_limits: Option<BenchLimits>,
    /// The family's reading of `address:` texts, for the files that extend this one.
    parse_address: Option<AddressParser>,
    /// What `--drive`, a recipe's `drive:` and messages call this dictionary: its file's
    /// name without `.yaml` (`ct-unidrive-sp`), which for a built-in one is its name.
    name: String,
    /// What works but should be written otherwise, in this file and the files that
    /// extended it (a family id's former spelling); `check` shows them.
    notes: Vec<Diagnostic>,
    /// Objects a device's file lists in types drivescript cannot access (TIME_OF_DAY …),
    /// for `objects` to show as such.
    not_accessible: Vec<FileEntry>,
    /// The motor's pole pairs its speed objects' rpm are given for, where it is an
    /// inverter's dictionary (`pole_pairs:`), and who set them.
    pole_pairs: Option<PolePairs>,
}

impl Dictionary {
    /// Reads, parses and checks a dictionary file. Every problem of the file is reported.
    pub fn load(path: impl AsRef<Path>) -> Result<Dictionary, DictionaryError> {
        Self::from_file(path.as_ref(), true, None)
    }

    /// Parses and checks dictionary text; `path` is only used in messages. Objects give
    /// `index:`/`subindex:` (an `address:` needs the family: [`Self::from_yaml_for`]).
    pub fn from_yaml(path: &str, text: &str) -> Result<Dictionary, DictionaryError> {
        Self::from_source(Source::new(path, text), true, None)
    }

    /// [`from_yaml`](Self::from_yaml) for a family whose `address:` notation `parse_address`
    /// reads; files that extend the dictionary later are read with it too.
    pub fn from_yaml_for(
        path: &str,
        text: &str,
        parse_address: AddressParser,
    ) -> Result<Dictionary, DictionaryError> {
        Self::from_source(Source::new(path, text), true, Some(parse_address))
    }

    /// Adds a user's objects (`--dictionary PATH`) to this dictionary. An object whose
    /// name is already in the dictionary replaces that object (same place in the list);
    /// other objects are appended. A `profile:` in `other` replaces the whole profile.
    /// Then everything is checked again (an alias clashing with a built-in name, a profile
    /// role now naming a string …); on any problem `self` is left unchanged.
    pub fn extend(&mut self, other: Dictionary) -> Result<(), DictionaryError> {
        let prefer = Arc::clone(other.family_span.source());
        if other.family != self.family {
            return Err(Diagnostic::at(
                &other.family_span,
                format!(
                    "this dictionary is for `{}`; it cannot extend the `{}` dictionary",
                    other.family, self.family
                ),
                "other family",
            )
            .with_help(format!("write `family: {}`", self.family))
            .into());
        }
        let mut merged = self.clone();
        // By name, ignoring case: an EDS adds thousands of objects at once.
        let mut at: HashMap<String, usize> = merged
            .objects
            .iter()
            .enumerate()
            .map(|(i, o)| (o.name.to_ascii_lowercase(), i))
            .collect();
        for object in other.objects {
            let key = object.name.to_ascii_lowercase();
            match at.get(&key) {
                Some(&i) => merged.objects[i] = object,
                None => {
                    at.insert(key, merged.objects.len());
                    merged.objects.push(object);
                }
            }
        }
        if other.profile.is_some() {
            merged.profile = other.profile;
        }
        // A file of the user's that says its motor's pole pairs speaks for the objects it
        // brings (their rpm are given for them) and for the whole dictionary: the objects
        // kept from this one are rescaled to them.
        if let Some(pairs) = other.pole_pairs {
            merged.rescale_for(pairs);
        }
        merged.notes.extend(other.notes);
        merged.not_accessible.extend(other.not_accessible);
        let problems = validate(&merged.objects, merged.profile.as_ref(), &[], Some(&prefer));
        if let Some(e) = DictionaryError::collect(problems) {
            return Err(e);
        }
        if let Some(limits) = merged.bench_limits.take() {
            merged.apply_bench_limits(limits);
        }
        *self = merged;
        Ok(())
    }

    /// Reads a user's dictionary file and [`extend`](Self::extend)s this one with it. Its
    /// profile may name objects of this dictionary, so roles are checked after merging.
    /// An EDS or DCF (CiA 306, `.eds`/`.dcf`) adds the objects it lists.
    pub fn extend_from(&mut self, path: impl AsRef<Path>) -> Result<(), DictionaryError> {
        if is_eds_path(path.as_ref()) {
            return self.extend_from_eds(path.as_ref(), &|_| None);
        }
        let other = Self::from_file(path.as_ref(), false, self.parse_address)?;
        self.extend(other)
    }

    /// The objects of an EDS or DCF added under readable names; an object at an address
    /// this dictionary already has keeps its name, unit and scale here (which an EDS does
    /// not give) and takes the file's type, access and limits (the device's own file wins;
    /// the object records what it replaced). No EDS name takes a name or alias already
    /// here. `family_alias` names an object in the family's own notation (the Lenze 9400's
    /// `C00099`), a first alias. A file that is not UTF-8 is read as Windows-1252, with a
    /// note saying so.
    pub fn extend_from_eds(
        &mut self,
        path: &Path,
        family_alias: &dyn Fn(&Address) -> Option<String>,
    ) -> Result<(), DictionaryError> {
        let (source, encoding_note) = read_eds_source(path)?;
        let mut problems = Diagnostics::new();
        let file = EdsFile::parse(&source, &mut problems);
        if let Some(e) = DictionaryError::collect(problems) {
            return Err(e);
        }
        let taken = self
            .objects
            .iter()
            .flat_map(|o| o.names())
            .map(str::to_ascii_lowercase)
            .collect();
        let occupied = self.objects.iter().map(|o| o.address).collect();
        let EdsObjects {
            objects,
            mut notes,
            aliases_of_occupied,
            on_built_in,
            not_carried,
            ..
        } = eds_objects(&file, &taken, &occupied, family_alias);
        notes.splice(0..0, encoding_note);
        let before = self.objects.clone();
        let at: HashMap<Address, usize> = self
            .objects
            .iter()
            .enumerate()
            .map(|(i, o)| (o.address, i))
            .collect();
        for (address, aliases) in aliases_of_occupied {
            if let Some(&i) = at.get(&address) {
                self.objects[i].aliases.extend(aliases);
            }
        }
        for OnBuiltIn {
            file,
            data_type,
            access,
            limits,
        } in on_built_in
        {
            if let Some(&i) = at.get(&file.address) {
                file.lay_over(&mut self.objects[i], data_type, access, limits);
            }
        }
        let added = self.extend(Dictionary {
            family: self.family.clone(),
            family_span: Span::start_of(&source),
            title: String::new(),
            objects,
            profile: None,
            bench_limits: None,
            parse_address: self.parse_address,
            name: file_stem(source.path()),
            notes,
            not_accessible: not_carried,
            pole_pairs: None,
        });
        if added.is_err() {
            self.objects = before;
        }
        added
    }

    fn from_file(
        path: &Path,
        check_roles: bool,
        parse_address: Option<AddressParser>,
    ) -> Result<Dictionary, DictionaryError> {
        let source = read_dictionary_source(path)?;
        Self::from_source(source, check_roles, parse_address)
    }

    fn from_source(
        file: Arc<Source>,
        check_roles: bool,
        parse_address: Option<AddressParser>,
    ) -> Result<Dictionary, DictionaryError> {
        if file.text().trim().is_empty() {
            return Err(Diagnostic::unlocated(file.path(), "the dictionary file is empty")
                .with_help("a dictionary starts with `family:` and lists its `objects:`")
                .into());
        }
        let root = YamlNode::parse(&file).map_err(|e| e.diagnostic(file.path(), None))?;
        let mut problems = Diagnostics::new();
        let contents = read(&root, &mut problems, parse_address);
        let profile = if check_roles {
            contents.profile.as_ref()
        } else {
            None
        };
        problems.extend(validate(&contents.objects, profile, &contents.broken, None));
        if let Some(e) = DictionaryError::collect(problems) {
            return Err(e);
        }
        Ok(Dictionary {
            family: contents.family,
            family_span: contents.family_span,
            title: contents.title,
            objects: contents.objects,
            profile: contents.profile,
            bench_limits: None,
            parse_address,
            name: file_stem(file.path()),
            notes: contents.notes,
            not_accessible: Vec::new(),
            pole_pairs: contents.pole_pairs.map(|count| PolePairs {
                count,
                origin: format!("the dictionary {}", file_stem(file.path())),
            }),
        })
    }

    /// Caps every writable object whose unit measures speed (or current) at the bench's
    /// limit: its maximum becomes the smaller of its own and the cap, its minimum the larger
    /// of its own and minus the cap. Refusals then name the bench limit and its file. Kept
    /// and applied again after every later [`Self::extend`].
    pub fn apply_bench_limits(&mut self, limits: BenchLimits) {
        let origin = limits.source();
        for object in self.objects.iter_mut().filter(|o| o.writable()) {
            let Some(unit) = object.unit else { continue };
            let dimension = unit.dimension();
            let Some(cap) = limits.cap(dimension) else {
                continue;
            };
            if let Some(cap) = dimension.base().convert(cap, unit) {
                object.cap_at(cap, &origin);
            }
        }
        self.bench_limits = Some(limits);
    }

    /// Sets the motor's pole pairs (`--link-option pole-pairs=N`, a recipe's
    /// `link: { pole_pairs: N }`): every speed object counting an inverter's output
    /// frequency has its rpm scale and limits recomputed for them (4-pole: half the rpm of
    /// 2-pole at the same Hz). Before the bench limits, which are in rpm and stay so. A
    /// dictionary that gives no `pole_pairs` is refused: its rpm are not a frequency.
    pub fn set_pole_pairs(&mut self, count: u32, origin: &str) -> Result<(), ValueError> {
        if self.pole_pairs.is_none() {
            return Err(ValueError::PolePairsNotUsed {
                dictionary: self.name.clone(),
                origin: origin.to_string(),
            });
        }
        self.rescale_for(PolePairs {
            count,
            origin: origin.to_string(),
        });
        Ok(())
    }

    /// Every speed object counting an inverter's output frequency rescaled from its pole
    /// pairs to `pairs`, which are then in force; the bench limits applied again after.
    fn rescale_for(&mut self, pairs: PolePairs) {
        for object in &mut self.objects {
            let Some(before) = object.pole_pairs else { continue };
            let factor = f64::from(before) / f64::from(pairs.count);
            object.scale *= factor;
            object.min = object.min.map(|m| m * factor);
            object.max = object.max.map(|m| m * factor);
            object.pole_pairs = Some(pairs.count);
        }
        self.pole_pairs = Some(pairs);
        if let Some(limits) = self.bench_limits.take() {
            self.apply_bench_limits(limits);
        }
    }

    /// The motor's pole pairs in force and who set them, for an inverter's dictionary.
    pub fn pole_pairs(&self) -> Option<&PolePairs> {
        self.pole_pairs.as_ref()
    }

    /// The bench limits in force, if any.
    pub fn bench_limits(&self) -> Option<&BenchLimits> {
        self.bench_limits.as_ref()
    }

    /// This dictionary's name: what `--drive` and a recipe's `drive:` say and what messages
    /// call it (`ct-unidrive-sp`), not the family it is for (see [`Self::family`]).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The id of the drive family this dictionary is for (its `family:`, e.g. `ct-ansi`):
    /// which protocol to speak, not what to call the dictionary.
    pub fn family(&self) -> &str {
        &self.family
    }

    /// True when a recipe's or script's `drive:` fits this dictionary: it names the
    /// dictionary itself or the family it is for.
    pub fn is_for_drive(&self, drive: &str) -> bool {
        drive == self.name || family_id(drive) == self.family
    }

    /// What works but should be written otherwise (an old `family:` spelling), each at
    /// its place, for `check` to show.
    pub fn notes(&self) -> &[Diagnostic] {
        &self.notes
    }

    /// Objects a device's file lists whose types drivescript cannot access, in file order.
    pub fn not_accessible(&self) -> &[FileEntry] {
        &self.not_accessible
    }

    pub fn title(&self) -> &str {
        &self.title
    }

    /// The object called `name` or having it as an alias, ignoring case. Otherwise an
    /// error with up to three close names.
    pub fn lookup(&self, name: &str) -> Result<&ObjectDef, UnknownObject> {
        self.get(name).ok_or_else(|| UnknownObject {
            name: name.to_string(),
            dictionary: self.name.clone(),
            suggestions: self.suggest(name),
        })
    }

    /// [`lookup`](Self::lookup) without the suggestions.
    pub fn get(&self, name: &str) -> Option<&ObjectDef> {
        // Recipes resolve aliases to the dictionary's names, so a run's millions of reads
        // find their object by an exact name; aliases and case are the slower fallback.
        self.objects
            .iter()
            .find(|o| o.name == name)
            .or_else(|| self.objects.iter().find(|o| o.is_named(name)))
    }

    /// Object names close to `name` (compared with names and aliases), best first.
    fn suggest(&self, name: &str) -> Vec<String> {
        let close = did_you_mean(name, self.objects.iter().flat_map(|o| o.names()));
        let mut names: Vec<String> = Vec::new();
        for n in close {
            if let Some(o) = self.get(&n) {
                if !names.contains(&o.name) {
                    names.push(o.name.clone());
                }
            }
        }
        names.truncate(3);
        names
    }

    /// The object at `index`/`subindex`.
    pub fn by_address(&self, index: u16, subindex: u32) -> Option<&ObjectDef> {
        let address = Address::Indexed { index, subindex };
        self.objects.iter().find(|o| o.address == address)
    }

    /// This dictionary with `object` added as it is, for one-off access to an object the
    /// files do not list (see `Family::raw_object`); names are not checked, so `#5.04`
    /// is allowed here and nowhere else.
    pub fn with_raw_object(&self, object: ObjectDef) -> Dictionary {
        let mut extended = self.clone();
        extended.objects.push(object);
        extended
    }

    /// Every object, in file order (a user's new objects after the built-in ones).
    pub fn objects(&self) -> impl Iterator<Item = &ObjectDef> {
        self.objects.iter()
    }

    /// Objects whose name, an alias or the description contains `text`, ignoring case
    /// (`drivescript objects FILTER`). An empty filter gives every object.
    pub fn filter(&self, text: &str) -> Vec<&ObjectDef> {
        let needle = text.trim().to_lowercase();
        self.objects
            .iter()
            .filter(|o| {
                needle.is_empty()
                    || o.names().any(|n| n.to_lowercase().contains(&needle))
                    || o.description.to_lowercase().contains(&needle)
            })
            .collect()
    }

    /// The device-control profile; `None` for a dictionary file that has none (a user's
    /// additions).
    pub fn profile(&self) -> Option<&Profile> {
        self.profile.as_ref()
    }

    /// The object playing `role` in the profile.
    pub fn role(&self, role: Role) -> Option<&ObjectDef> {
        self.get(self.profile.as_ref()?.object(role)?)
    }
}
/// A dictionary file's text, or the error that says why it could not be read.
fn read_dictionary_source(path: &Path) -> Result<Arc<Source>, DictionaryError> {
    read_source(path).map_err(|e| {
        let help = e
            .help()
            .unwrap_or_else(|| "check the path given with --dictionary".into());
        Diagnostic::unlocated(path.display().to_string(), e.sentence("the dictionary file"))
            .with_help(help)
            .into()
    })
}

/// An EDS or DCF's text: UTF-8, or else Windows-1252 (vendor tools write it; every byte
/// is a character there, so nothing is lost) with a note saying so once.
fn read_eds_source(path: &Path) -> Result<(Arc<Source>, Option<Diagnostic>), DictionaryError> {
    let shown = path.display().to_string();
    let (text, windows) = crate::diag::read_text_or_windows_1252(path).map_err(|e| {
        let help = e
            .help()
            .unwrap_or_else(|| "check the path given with --dictionary".into());
        Diagnostic::unlocated(&shown, e.sentence("the dictionary file")).with_help(help)
    })?;
    let note = windows.then(|| {
        Diagnostic::unlocated(
            &shown,
            "the file is not UTF-8; it is read as Windows-1252, the encoding vendor tools write EDS files in",
        )
        .with_help("to silence this note, save the file as UTF-8: iconv -f WINDOWS-1252 -t UTF-8 FILE > NEW")
    });
    Ok((Source::new(shown, text), note))
}

/// A dictionary file's name without its folder and extension: `dictionary/sd2.yaml` → `sd2`.
fn file_stem(path: &str) -> String {
    Path::new(path)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.to_string())
}
