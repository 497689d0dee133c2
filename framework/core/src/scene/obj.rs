//! Wavefront OBJ/MTL loading.
//!
//! The text is first checked line by line here, so that a malformed file is reported with its
//! name, line number and the offending value, and then handed (normalized: comments stripped,
//! colour-only vertex data dropped, `v x y z w` divided through) to `tobj`, which triangulates
//! the faces and builds a single vertex index.

use std::collections::{HashMap, HashSet};
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::TextureFile;
use super::{IllumModel, Material, MaterialId, Mesh, Texture};
use crate::Error;
use crate::film::{LoadBudget, read_text_bounded};

/// A loaded OBJ file: all of its objects merged into one triangle mesh, and its materials.
#[derive(Clone, Debug, Default)]
pub struct ObjData {
    /// The triangles of every object in the file; `face_materials` index into `materials`.
    pub mesh: Mesh,
    /// The materials of the file's material libraries (in the order they are defined), plus a
    /// Lambertian material named `"default"` (reflectance 0.8) when some face has none.
    pub materials: Vec<Material>,
}

/// Reads the text of a file that another file refers to (an MTL library, an OBJ mesh).
pub(crate) type ReadText<'a> = &'a dyn Fn(&Path) -> io::Result<String>;

/// Reads a text file from disk under the [`LoadBudget::current`] budget: a regular file, not
/// too large, UTF-8.
pub(crate) fn read_text(path: &Path) -> io::Result<String> {
    read_text_bounded(path, &LoadBudget::current())
}

/// Loads an OBJ file and the MTL libraries it names (relative to the OBJ's directory); diffuse
/// textures (`map_Kd`) are loaded relative to their MTL file's directory.
pub fn load_obj(path: &Path) -> Result<ObjData, Error> {
    let text = read_text(path).map_err(|e| Error::io(path, e))?;
    load_obj_with(path, &text, &|p: &Path| read_text(p))
}

/// Loads OBJ text held in memory, with the text of its material library (every `mtllib`
/// statement refers to `mtl`). `name` stands for the file in error messages, and textures are
/// loaded relative to its directory.
pub fn load_obj_str(name: &str, obj: &str, mtl: Option<&str>) -> Result<ObjData, Error> {
    load_obj_with(Path::new(name), obj, &|_: &Path| match mtl {
        Some(text) => Ok(text.to_string()),
        None => Err(io::Error::new(
            io::ErrorKind::NotFound,
            "no MTL text was given along with the OBJ text",
        )),
    })
}

/// Loads OBJ `text` that stands for the file `path`, reading its material libraries through
/// `read`.
pub(crate) fn load_obj_with(path: &Path, text: &str, read: ReadText<'_>) -> Result<ObjData, Error> {
    let dir = path.parent().unwrap_or(Path::new(""));
    let checked = check_obj(path, dir, text, read)?;
    let libs = checked.libs;
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    // The text tobj reads has been checked line by line; a panic of tobj on it would still be
    // a bug of ours, reported as an error about the file rather than a crash.
    let parsed = crate::panic::catch_panic(|| {
        tobj::load_obj_buf(&mut checked.text.as_bytes(), &options, |p: &Path| {
            let key = p.to_string_lossy();
            match libs.get(key.as_ref()) {
                Some(mtl) => tobj::load_mtl_buf(&mut mtl.as_bytes()),
                None => Err(tobj::LoadError::OpenFileFailed),
            }
        })
    })
    .map_err(|caught| Error::Parse {
        path: path.to_path_buf(),
        line: 0,
        reason: format!(
            "the OBJ reader failed on the file (it panicked: {})",
            caught.message
        ),
    })?;
    let (models, tobj_materials) = parsed.map_err(|e| Error::Parse {
        path: path.to_path_buf(),
        line: 0,
        reason: format!("the OBJ reader rejected the file: {e}"),
    })?;
    let tobj_materials = tobj_materials.map_err(|e| Error::Parse {
        path: path.to_path_buf(),
        line: 0,
        reason: format!("the MTL reader rejected a material library: {e}"),
    })?;

    let mut textures = HashMap::new();
    let mut materials = Vec::with_capacity(tobj_materials.len() + 1);
    for (i, m) in tobj_materials.iter().enumerate() {
        // Textures are relative to the MTL file that defines the material.
        let (mtl_path, texture_line) = checked
            .material_sources
            .get(i)
            .map_or((path, None), |(p, line)| (p.as_path(), *line));
        materials.push(convert_material(m, mtl_path, texture_line, &mut textures)?);
    }

    let default_id = MaterialId(materials.len() as u32);
    let mut needs_default = false;
    let mut mesh = Mesh::default();
    for model in &models {
        let m = &model.mesh;
        if m.indices.is_empty() {
            continue;
        }
        let n = m.positions.len() / 3;
        let bad_index = m.indices.iter().any(|&i| i as usize >= n);
        if bad_index || m.indices.len() % 3 != 0 {
            return Err(Error::Parse {
                path: path.to_path_buf(),
                line: 0,
                reason: format!(
                    "object '{}' has a face that refers to a missing vertex",
                    model.name
                ),
            });
        }
        let material = match m.material_id {
            Some(id) if id < materials.len() => MaterialId(id as u32),
            _ => {
                needs_default = true;
                default_id
            }
        };
        let positions = m
            .positions
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect();
        // With a single index, vertices that lack a normal (or texture coordinate) get none, so
        // an object that mixes `v/vt/vn` and `v` references has fewer of them than vertices:
        // then the face normals (and no texture coordinates) are used for the whole object.
        let normals = if m.normals.len() == 3 * n {
            m.normals
                .chunks_exact(3)
                .map(|c| Vec3::new(c[0], c[1], c[2]).normalize_or_zero())
                .collect()
        } else {
            Vec::new()
        };
        let texcoords = if m.texcoords.len() == 2 * n {
            m.texcoords
                .chunks_exact(2)
                .map(|c| Vec2::new(c[0], c[1]))
                .collect()
        } else {
            Vec::new()
        };
        let faces: Vec<[u32; 3]> = m
            .indices
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        let face_materials = vec![material; faces.len()];
        mesh.append(&Mesh {
            positions,
            normals,
            texcoords,
            faces,
            face_materials,
        });
    }
    if needs_default {
        materials.push(Material::lambertian("default", Vec3::splat(0.8)));
    }
    Ok(ObjData { mesh, materials })
}

/// The MTL `illum` numbers raylab has a shader for, as a readable list.
pub(crate) fn accepted_illums() -> String {
    (0..=u8::MAX)
        .filter(|&i| IllumModel::from_illum(i).is_some())
        .map(|i| i.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// A list of names for an error message (the first few of them).
pub(crate) fn name_list<S: AsRef<str>>(names: &[S]) -> String {
    const SHOWN: usize = 20;
    let mut list = names
        .iter()
        .take(SHOWN)
        .map(|s| format!("'{}'", s.as_ref().escape_debug()))
        .collect::<Vec<_>>()
        .join(", ");
    if names.len() > SHOWN {
        list.push_str(&format!(" and {} more", names.len() - SHOWN));
    }
    list
}

/// An OBJ file after the line-by-line check.
struct CheckedObj {
    /// Normalized text for tobj, one line per input line.
    text: String,
    /// Normalized MTL text by the name the `mtllib` statement uses.
    libs: HashMap<String, String>,
    /// For each material tobj will return (in its order), the MTL file it comes from and the
    /// line of its `map_Kd` statement, if it has one.
    material_sources: Vec<(PathBuf, Option<usize>)>,
}

/// The parse error at line `line` of `path`, for a reason.
fn parse_error(path: &Path, line: usize) -> impl Fn(String) -> Error + Copy + '_ {
    move |reason| Error::Parse {
        path: path.to_path_buf(),
        line,
        reason,
    }
}

/// The lines of an OBJ or MTL file's `text`: each one's number (from 1), its text without the
/// comment, its statement's keyword (empty on a blank or comment-only line) and the words after
/// the keyword.
fn statements(text: &str) -> impl Iterator<Item = (usize, &str, &str, Vec<&str>)> {
    text.lines().enumerate().map(|(i, raw)| {
        let content = raw.split_once('#').map_or(raw, |(before, _)| before);
        let mut words = content.split_whitespace();
        let keyword = words.next().unwrap_or_default();
        (i + 1, content, keyword, words.collect())
    })
}

/// The text after the statement keyword (file and material names may contain spaces).
fn rest_of_statement<'a>(content: &'a str, keyword: &str) -> &'a str {
    content.trim_start()[keyword.len()..].trim()
}

/// Parses `args` as finite numbers; the error names `what` (e.g. "vertex") and the `part`
/// (e.g. "coordinate") at fault.
fn parse_numbers(args: &[&str], what: &str, part: &str) -> Result<Vec<f32>, String> {
    args.iter()
        .map(|tok| {
            let x: f32 = tok
                .parse()
                .map_err(|_| format!("{what} has malformed {part} '{tok}'; expected a number"))?;
            if x.is_finite() {
                Ok(x)
            } else {
                Err(format!(
                    "{what} has non-finite {part} '{tok}'; expected finite numbers"
                ))
            }
        })
        .collect()
}

/// Checks one vertex reference (`v`, `v/vt`, `v//vn` or `v/vt/vn`) of a face or line element
/// against the numbers of vertices, texture coordinates and normals defined so far.
fn check_reference(tok: &str, what: &str, counts: [usize; 3]) -> Result<(), String> {
    const KIND: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    const PLURAL: [&str; 3] = ["vertices", "texture coordinates", "normals"];
    let parts: Vec<&str> = tok.split('/').collect();
    if parts.len() > 3 || parts[0].is_empty() {
        return Err(format!(
            "{what} has malformed vertex reference '{tok}'; expected v, v/vt, v//vn or v/vt/vn"
        ));
    }
    for (k, part) in parts.iter().enumerate() {
        if part.is_empty() {
            continue;
        }
        let i: i64 = part.parse().map_err(|_| {
            format!(
                "{what} has malformed vertex reference '{tok}': '{part}' is not an integer index"
            )
        })?;
        let n = counts[k] as i64;
        if i == 0 {
            return Err(format!(
                "{what} has {} index 0 in '{tok}'; OBJ indices start at 1 (or count back from -1)",
                KIND[k]
            ));
        }
        if i > n || i < -n {
            let context = if tok == *part {
                String::new()
            } else {
                format!(" (in '{tok}')")
            };
            return Err(format!(
                "{what} refers to {} {i}{context} but only {n} {} are defined before this line",
                KIND[k], PLURAL[k]
            ));
        }
    }
    Ok(())
}

/// Checks an OBJ file line by line, reads and checks its material libraries, and produces the
/// normalized text for tobj.
fn check_obj(path: &Path, dir: &Path, text: &str, read: ReadText<'_>) -> Result<CheckedObj, Error> {
    let mut out = String::with_capacity(text.len());
    let mut libs: HashMap<String, String> = HashMap::new();
    let mut material_sources = Vec::new();
    let mut lib_files: Vec<String> = Vec::new();
    let mut known: Vec<String> = Vec::new();
    let mut known_set: HashSet<String> = HashSet::new();
    // Vertices, texture coordinates and normals defined so far.
    let mut counts = [0usize; 3];
    for (line_no, content, keyword, args) in statements(text) {
        let fail = parse_error(path, line_no);
        match keyword {
            "v" => {
                let v = parse_numbers(&args, "vertex", "coordinate").map_err(fail)?;
                let w = match v.len() {
                    3 | 6 => 1.0,
                    4 => v[3],
                    n => {
                        return Err(fail(format!(
                            "vertex has {n} numbers; expected 3 (v x y z), 4 (with a weight w) or 6 (with an RGB colour)"
                        )));
                    }
                };
                if w == 0.0 {
                    return Err(fail(
                        "vertex has weight w = 0; expected a non-zero weight".into(),
                    ));
                }
                let p = Vec3::new(v[0], v[1], v[2]) / w;
                if !p.is_finite() {
                    return Err(fail(format!(
                        "vertex ({}, {}, {}) / w = {w} is not finite; expected finite numbers",
                        v[0], v[1], v[2]
                    )));
                }
                out.push_str(&format!("v {} {} {}\n", p.x, p.y, p.z));
                counts[0] += 1;
            }
            "vt" => {
                let t = parse_numbers(&args, "texture coordinate", "component").map_err(fail)?;
                if t.is_empty() || t.len() > 3 {
                    return Err(fail(format!(
                        "texture coordinate has {} numbers; expected 1 to 3 (vt u [v [w]])",
                        t.len()
                    )));
                }
                out.push_str(&format!(
                    "vt {} {}\n",
                    t[0],
                    t.get(1).copied().unwrap_or(0.0)
                ));
                counts[1] += 1;
            }
            "vn" => {
                let n = parse_numbers(&args, "normal", "coordinate").map_err(fail)?;
                if n.len() != 3 {
                    return Err(fail(format!(
                        "normal has {} numbers; expected 3 (vn x y z)",
                        n.len()
                    )));
                }
                out.push_str(&format!("vn {} {} {}\n", n[0], n[1], n[2]));
                counts[2] += 1;
            }
            "f" => {
                if args.len() < 3 {
                    return Err(fail(format!(
                        "face has {} vertex references; expected at least 3",
                        args.len()
                    )));
                }
                for tok in &args {
                    check_reference(tok, "face", counts).map_err(fail)?;
                }
                out.push_str("f ");
                out.push_str(&args.join(" "));
                out.push('\n');
            }
            "l" => {
                // Line elements are not surfaces: checked, then left out.
                if args.len() < 2 {
                    return Err(fail(format!(
                        "line element has {} vertex references; expected at least 2",
                        args.len()
                    )));
                }
                for tok in &args {
                    check_reference(tok, "line element", counts).map_err(fail)?;
                }
                out.push('\n');
            }
            "o" | "g" => {
                out.push_str(content.trim());
                out.push('\n');
            }
            "mtllib" => {
                let name = rest_of_statement(content, keyword);
                if name.is_empty() {
                    return Err(fail(
                        "mtllib without a file name; expected mtllib FILE.mtl".into(),
                    ));
                }
                let mtl_path = dir.join(name);
                let mtl_text = read(&mtl_path).map_err(|e| {
                    fail(format!(
                        "cannot read the material library '{}' named by 'mtllib {name}': {e}",
                        mtl_path.display()
                    ))
                })?;
                let (clean, names) = check_mtl(&mtl_path, &mtl_text)?;
                for (n, texture_line) in &names {
                    material_sources.push((mtl_path.clone(), *texture_line));
                    if known_set.insert(n.clone()) {
                        known.push(n.clone());
                    }
                }
                libs.insert(name.to_string(), clean);
                lib_files.push(mtl_path.display().to_string());
                out.push_str(&format!("mtllib {name}\n"));
            }
            "usemtl" => {
                let name = rest_of_statement(content, keyword);
                if name.is_empty() {
                    return Err(fail(
                        "usemtl without a material name; expected usemtl NAME".into(),
                    ));
                }
                if !known_set.contains(name) {
                    return Err(fail(if lib_files.is_empty() {
                        format!(
                            "usemtl '{name}' but no material library was loaded (mtllib) before this line"
                        )
                    } else if known.is_empty() {
                        format!(
                            "usemtl '{name}' but the material libraries {} define no materials",
                            name_list(&lib_files)
                        )
                    } else {
                        format!(
                            "usemtl '{name}': no such material in {}; expected one of {}",
                            name_list(&lib_files),
                            name_list(&known)
                        )
                    }));
                }
                out.push_str(&format!("usemtl {name}\n"));
            }
            // Everything else (s, p, curves, ...) is ignored, as OBJ permits.
            _ => out.push('\n'),
        }
    }
    Ok(CheckedObj {
        text: out,
        libs,
        material_sources,
    })
}

/// A material's name and the line of its `map_Kd` statement, if any.
type MtlEntry = (String, Option<usize>);

/// Checks an MTL file line by line; returns the normalized text for tobj and the materials in
/// the order they are defined.
fn check_mtl(path: &Path, text: &str) -> Result<(String, Vec<MtlEntry>), Error> {
    let mut out = String::with_capacity(text.len());
    let mut names = Vec::new();
    for (line_no, content, keyword, args) in statements(text) {
        let fail = parse_error(path, line_no);
        match keyword {
            "newmtl" => {
                let name = rest_of_statement(content, keyword);
                if name.is_empty() {
                    return Err(fail("newmtl without a name; expected newmtl NAME".into()));
                }
                names.push((name.to_string(), None));
                out.push_str(&format!("newmtl {name}\n"));
            }
            "Ka" | "Kd" | "Ks" | "Ke" | "Tf" => {
                if let Some(form @ ("spectral" | "xyz")) = args.first().copied() {
                    return Err(fail(format!(
                        "'{keyword} {form}' is not supported; expected an RGB colour ({keyword} r g b)"
                    )));
                }
                let c = parse_numbers(&args, keyword, "value").map_err(fail)?;
                let c = match c.len() {
                    1 => [c[0]; 3],
                    3 => [c[0], c[1], c[2]],
                    n => {
                        return Err(fail(format!(
                            "{keyword} has {n} numbers; expected 3 ({keyword} r g b)"
                        )));
                    }
                };
                if let Some(x) = c.iter().find(|x| **x < 0.0) {
                    return Err(fail(format!(
                        "{keyword} has negative value {x}; expected non-negative numbers"
                    )));
                }
                out.push_str(&format!("{keyword} {} {} {}\n", c[0], c[1], c[2]));
            }
            "Ns" | "Ni" | "d" => {
                let v = parse_numbers(&args, keyword, "value").map_err(fail)?;
                if v.len() != 1 {
                    return Err(fail(format!(
                        "{keyword} has {} numbers; expected 1 ({keyword} value)",
                        v.len()
                    )));
                }
                if keyword == "Ni" && v[0] <= 0.0 {
                    return Err(fail(format!(
                        "Ni (index of refraction) is {}; expected a positive number",
                        v[0]
                    )));
                }
                if keyword == "Ns" && v[0] < 0.0 {
                    return Err(fail(format!(
                        "Ns (shininess) is {}; expected a non-negative number",
                        v[0]
                    )));
                }
                out.push_str(&format!("{keyword} {}\n", v[0]));
            }
            "Pr" => {
                let v = parse_numbers(&args, keyword, "value").map_err(fail)?;
                match v.as_slice() {
                    [r] if *r > 0.0 && *r <= 1.0 => out.push_str(&format!("Pr {r}\n")),
                    [r] => {
                        return Err(fail(format!(
                            "Pr (roughness) is {r}; expected a number in (0, 1]"
                        )));
                    }
                    _ => {
                        return Err(fail(format!(
                            "Pr has {} numbers; expected 1 (Pr roughness)",
                            v.len()
                        )));
                    }
                }
            }
            "illum" => {
                let model = match args.as_slice() {
                    [value] => value.parse::<u8>().ok().and_then(IllumModel::from_illum),
                    _ => None,
                };
                if model.is_none() {
                    return Err(fail(format!(
                        "illum '{}' has no raylab shader; expected one of {}",
                        args.join(" "),
                        accepted_illums()
                    )));
                }
                out.push_str(&format!("illum {}\n", args[0]));
            }
            "map_Kd" => {
                let file = texture_statement(rest_of_statement(content, keyword)).map_err(fail)?;
                if let Some((_, texture_line)) = names.last_mut() {
                    *texture_line = Some(line_no);
                }
                out.push_str(&format!("map_Kd {file}\n"));
            }
            // Other statements (other texture maps, Tr, ...) are not used by raylab.
            _ => out.push('\n'),
        }
    }
    Ok((out, names))
}

/// The arguments of an MTL texture option, and those with which the option changes nothing in
/// raylab's lookup (the coordinates as given, the render's filter and addressing, no mip maps,
/// RGB).
enum OptionArgs {
    /// `on` or `off`; the value that changes nothing, if one does.
    Switch(Option<&'static str>),
    /// From `min` to `max` numbers, and the numbers that change nothing (compared with those
    /// given): `None` when every value is refused, `&[]` when every value is accepted.
    Numbers(usize, usize, Option<&'static [f32]>),
    /// One word (`-imfchan r`): always refused for an RGB texture.
    Word,
}

/// The options of MTL texture statements (`map_Kd -s 2 2 1 file.png`): name, what it does,
/// and its arguments.
const TEXTURE_OPTIONS: [(&str, &str, OptionArgs); 13] = [
    ("-blendu", "blending across u", OptionArgs::Switch(None)),
    ("-blendv", "blending across v", OptionArgs::Switch(None)),
    (
        "-boost",
        "mip-map sharpness",
        OptionArgs::Numbers(1, 1, Some(&[])),
    ),
    ("-cc", "colour correction", OptionArgs::Switch(Some("off"))),
    (
        "-clamp",
        "clamping of the texture coordinates",
        OptionArgs::Switch(Some("off")),
    ),
    (
        "-mm",
        "a value range (base, gain)",
        OptionArgs::Numbers(2, 2, Some(&[0.0, 1.0])),
    ),
    (
        "-o",
        "an offset of the texture coordinates",
        OptionArgs::Numbers(1, 3, Some(&[0.0, 0.0, 0.0])),
    ),
    (
        "-s",
        "a scale of the texture coordinates",
        OptionArgs::Numbers(1, 3, Some(&[1.0, 1.0, 1.0])),
    ),
    (
        "-t",
        "turbulence",
        OptionArgs::Numbers(1, 3, Some(&[0.0, 0.0, 0.0])),
    ),
    (
        "-texres",
        "resampling to a resolution",
        OptionArgs::Numbers(1, 1, None),
    ),
    (
        "-bm",
        "a bump multiplier",
        OptionArgs::Numbers(1, 1, Some(&[1.0])),
    ),
    (
        "-imfchan",
        "a single channel of the image",
        OptionArgs::Word,
    ),
    ("-type", "a reflection map's projection", OptionArgs::Word),
];

/// Parses the arguments of a `map_Kd` statement: its options (see [`TEXTURE_OPTIONS`]), each
/// accepted when it changes nothing in raylab's texture lookup (`-blendu`/`-blendv` and
/// `-boost` with any value: there is no blending or mip map; the others at their neutral
/// values) and refused otherwise, and the file name after them (which may contain spaces).
fn texture_statement(spec: &str) -> Result<&str, String> {
    let mut rest = spec.trim_start();
    let next_word = |rest: &str| rest.split_whitespace().next().map(str::to_owned);
    while let Some(word) = next_word(rest).filter(|w| w.starts_with('-') && w.len() > 1) {
        let Some((name, what, args)) = TEXTURE_OPTIONS.iter().find(|o| o.0 == word) else {
            return Err(format!(
                "map_Kd has unknown option '{word}'; expected one of {} before the file name",
                TEXTURE_OPTIONS.map(|o| o.0).join(", ")
            ));
        };
        rest = rest[word.len()..].trim_start();
        let mut values: Vec<String> = Vec::new();
        let (min, max) = match args {
            OptionArgs::Numbers(min, max, _) => (*min, *max),
            _ => (1, 1),
        };
        while values.len() < max {
            let Some(arg) = next_word(rest) else { break };
            let fits = match args {
                OptionArgs::Numbers(..) => arg.parse::<f32>().is_ok_and(f32::is_finite),
                OptionArgs::Switch(_) => arg == "on" || arg == "off",
                OptionArgs::Word => true,
            };
            if !fits {
                break;
            }
            rest = rest[arg.len()..].trim_start();
            values.push(arg);
        }
        if values.len() < min {
            let expected = match args {
                OptionArgs::Switch(_) => "on or off".to_string(),
                OptionArgs::Word => "a value".to_string(),
                OptionArgs::Numbers(a, b, _) if a == b => format!("{a} finite number(s)"),
                OptionArgs::Numbers(a, b, _) => format!("{a} to {b} finite numbers"),
            };
            return Err(format!(
                "map_Kd option {name} ({what}) is followed by {}; expected {expected}",
                next_word(rest).map_or("nothing".to_string(), |w| format!("'{w}'"))
            ));
        }
        let accepted = match args {
            OptionArgs::Switch(None) => true,
            OptionArgs::Switch(Some(neutral)) => values[0] == *neutral,
            OptionArgs::Numbers(_, _, None) | OptionArgs::Word => false,
            OptionArgs::Numbers(_, _, Some(neutral)) => values
                .iter()
                .zip(neutral.iter())
                .all(|(v, n)| v.parse::<f32>().ok() == Some(*n)),
        };
        if !accepted {
            return Err(format!(
                "map_Kd option '{name} {}' ({what}) is not supported: raylab looks a texture up \
                 at the texture coordinates as given, with the render's filter and addressing \
                 (lab 09); remove the option{}",
                values.join(" "),
                if matches!(*name, "-s" | "-o") {
                    " and transform the texture coordinates (vt) in the OBJ instead"
                } else {
                    ""
                }
            ));
        }
    }
    let file = rest.trim();
    if file.is_empty() {
        return Err("map_Kd without a file name; expected map_Kd [OPTIONS] FILE".into());
    }
    Ok(file)
}

/// Three numbers from a statement that tobj keeps as an unknown parameter (`Ke`, `Tf`).
fn unknown_rgb(m: &tobj::Material, key: &str) -> Option<Vec3> {
    let v: Vec<f32> = m
        .unknown_param
        .get(key)?
        .split_whitespace()
        .map(str::parse)
        .collect::<Result<_, _>>()
        .ok()?;
    match v.as_slice() {
        [x] => Some(Vec3::splat(*x)),
        [x, y, z] => Some(Vec3::new(*x, *y, *z)),
        _ => None,
    }
}

/// A raylab material from a tobj material defined in the MTL file `mtl_path`.
fn convert_material(
    m: &tobj::Material,
    mtl_path: &Path,
    texture_line: Option<usize>,
    textures: &mut HashMap<PathBuf, Arc<Texture>>,
) -> Result<Material, Error> {
    let illum = match m.illumination_model {
        None => IllumModel::Lambertian,
        Some(i) => IllumModel::from_illum(i).ok_or_else(|| Error::Parse {
            path: mtl_path.to_path_buf(),
            line: 0,
            reason: format!(
                "material '{}': illum {i} has no raylab shader; expected one of {}",
                m.name,
                accepted_illums()
            ),
        })?,
    };
    let diffuse_texture = match &m.diffuse_texture {
        None => None,
        Some(spec) => {
            let file = mtl_path.parent().unwrap_or(Path::new("")).join(spec);
            let texture = match textures.get(&file) {
                Some(t) => t.clone(),
                None => {
                    let statement = format!(
                        "the texture map_Kd of material '{}' at {}:{}",
                        m.name,
                        mtl_path.display(),
                        texture_line.unwrap_or(0)
                    );
                    let t = Arc::new(Texture::load_for(&file, &statement)?);
                    textures.insert(file, t.clone());
                    t
                }
            };
            Some(texture)
        }
    };
    Ok(Material {
        name: m.name.clone(),
        illum,
        diffuse: m.diffuse.map_or(Vec3::splat(0.8), Vec3::from),
        specular: m.specular.map_or(Vec3::ZERO, Vec3::from),
        ambient: m.ambient.map_or(Vec3::ZERO, Vec3::from),
        emission: m
            .emissive
            .map(Vec3::from)
            .or_else(|| unknown_rgb(m, "Ke"))
            .unwrap_or(Vec3::ZERO),
        shininess: m.shininess.unwrap_or(0.0),
        roughness: m
            .unknown_param
            .get("Pr")
            .and_then(|r| r.trim().parse().ok()),
        ior: m.optical_density.unwrap_or(1.0),
        transmission: unknown_rgb(m, "Tf").unwrap_or(Vec3::ONE),
        diffuse_texture,
        model: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh, empty directory under the system's temporary directory.
    fn temp_dir(tag: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("raylab-obj-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// The parse error of `obj` (with `mtl`), as (path, line, reason, full message).
    fn parse_error(obj: &str, mtl: Option<&str>) -> (PathBuf, usize, String, String) {
        match load_obj_str("test.obj", obj, mtl) {
            Err(e @ Error::Parse { .. }) => {
                let message = e.to_string();
                let Error::Parse { path, line, reason } = e else {
                    unreachable!()
                };
                (path, line, reason, message)
            }
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

    #[test]
    fn malformed_vertex_names_file_line_and_value() {
        let (path, line, reason, message) = parse_error("v 0 0 0\nv 1 2 abc\n", None);
        assert_eq!(path, Path::new("test.obj"));
        assert_eq!(line, 2);
        assert!(reason.contains("'abc'"), "{reason}");
        assert!(message.starts_with("test.obj:2: "), "{message}");
    }

    #[test]
    fn non_finite_vertex_is_rejected() {
        let (_, line, reason, _) = parse_error("# comment\nv nan 0 0\n", None);
        assert_eq!(line, 2);
        assert_eq!(
            reason,
            "vertex has non-finite coordinate 'nan'; expected finite numbers"
        );
        let (_, line, reason, _) = parse_error(&format!("{SQUARE}vn 0 inf 1\n"), None);
        assert_eq!(line, 5);
        assert!(
            reason.contains("normal") && reason.contains("'inf'"),
            "{reason}"
        );
        let (_, _, reason, _) = parse_error("vt 0.5 1e40\n", None);
        assert!(reason.contains("'1e40'"), "{reason}");
    }

    #[test]
    fn wrong_number_counts_are_rejected() {
        let (_, line, reason, _) = parse_error("v 1 2\n", None);
        assert_eq!(line, 1);
        assert!(
            reason.contains("2 numbers") && reason.contains("expected 3"),
            "{reason}"
        );
        let (_, _, reason, _) = parse_error("vn 1 2\n", None);
        assert!(reason.contains("expected 3"), "{reason}");
        let (_, _, reason, _) = parse_error("vt\n", None);
        assert!(reason.contains("expected 1 to 3"), "{reason}");
        let (_, _, reason, _) = parse_error("v 1 2 3 0\n", None);
        assert!(reason.contains("w = 0"), "{reason}");
    }

    #[test]
    fn face_indices_out_of_range_are_rejected() {
        let (_, line, reason, _) = parse_error(&format!("{SQUARE}f 1 2 9\n"), None);
        assert_eq!(line, 5);
        assert!(
            reason.contains("vertex 9") && reason.contains("only 4"),
            "{reason}"
        );
        let (_, _, reason, _) = parse_error(&format!("{SQUARE}f -1 -2 -5\n"), None);
        assert!(reason.contains("vertex -5"), "{reason}");
        let (_, _, reason, _) = parse_error(&format!("{SQUARE}f 0 1 2\n"), None);
        assert!(reason.contains("index 0"), "{reason}");
        let (_, _, reason, _) = parse_error(&format!("{SQUARE}vt 0 0\nf 1/1 2/2 3/1\n"), None);
        assert!(reason.contains("texture coordinate 2"), "{reason}");
        let (_, _, reason, _) = parse_error(&format!("{SQUARE}f 1//1 2//1 3//1\n"), None);
        assert!(
            reason.contains("normal 1") && reason.contains("only 0"),
            "{reason}"
        );
        let (_, _, reason, _) = parse_error(&format!("{SQUARE}f 1 2\n"), None);
        assert!(reason.contains("at least 3"), "{reason}");
        let (_, _, reason, _) = parse_error(&format!("{SQUARE}f 1 2 x\n"), None);
        assert!(reason.contains("'x'"), "{reason}");
        let (_, _, reason, _) = parse_error(&format!("{SQUARE}f 1/1/1/1 2 3\n"), None);
        assert!(reason.contains("malformed vertex reference"), "{reason}");
        // A vertex defined after the face that uses it.
        let (_, line, _, _) = parse_error("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n", None);
        assert_eq!(line, 3);
    }

    #[test]
    fn negative_indices_and_polygons_load() {
        let data = load_obj_str("quad.obj", &format!("{SQUARE}f -4 -3 -2 -1\n"), None).unwrap();
        assert_eq!(data.mesh.faces.len(), 2);
        assert_eq!(data.mesh.positions.len(), 4);
        let [a, b, c] = data.mesh.triangle(1);
        assert_eq!([a, b, c], [Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0), Vec3::Y]);
        // No material: everything gets the appended default material.
        assert_eq!(data.materials.len(), 1);
        assert_eq!(data.materials[0].name, "default");
        assert_eq!(data.materials[0].diffuse, Vec3::splat(0.8));
        assert!(data.mesh.face_materials.iter().all(|&m| m == MaterialId(0)));
    }

    #[test]
    fn missing_file_is_an_io_error_naming_it() {
        let path = Path::new("/nonexistent/raylab/missing.obj");
        match load_obj(path) {
            Err(e @ Error::Io { .. }) => assert!(e.to_string().contains("missing.obj"), "{e}"),
            other => panic!("expected an I/O error, got {other:?}"),
        }
    }

    #[test]
    fn missing_mtllib_names_both_files() {
        let dir = temp_dir("missing-mtl");
        let obj = dir.join("scene.obj");
        std::fs::write(&obj, format!("mtllib nothere.mtl\n{SQUARE}f 1 2 3\n")).unwrap();
        match load_obj(&obj) {
            Err(e @ Error::Parse { line: 1, .. }) => {
                let message = e.to_string();
                assert!(message.contains("scene.obj:1"), "{message}");
                assert!(message.contains("nothere.mtl"), "{message}");
            }
            other => panic!("expected a parse error, got {other:?}"),
        }
        // In memory, without MTL text.
        let (_, line, reason, _) = parse_error("mtllib x.mtl\n", None);
        assert_eq!(line, 1);
        assert!(reason.contains("x.mtl"), "{reason}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn bad_illum_names_mtl_file_line_value_and_accepted() {
        let obj = format!("mtllib m.mtl\n{SQUARE}usemtl a\nf 1 2 3\n");
        let (path, line, reason, message) =
            parse_error(&obj, Some("newmtl a\nKd 1 1 1\nillum 9\n"));
        assert_eq!(path, Path::new("m.mtl"));
        assert_eq!(line, 3);
        assert!(reason.contains("illum '9'"), "{reason}");
        assert!(
            reason.contains("0, 1, 2, 3, 4, 5, 6, 7, 11, 12"),
            "{reason}"
        );
        assert!(message.starts_with("m.mtl:3:"), "{message}");
        let (_, _, reason, _) = parse_error(&obj, Some("newmtl a\nillum two\n"));
        assert!(reason.contains("'two'"), "{reason}");
    }

    #[test]
    fn bad_mtl_values_are_rejected() {
        let obj = format!("mtllib m.mtl\n{SQUARE}usemtl a\nf 1 2 3\n");
        let (path, line, reason, _) = parse_error(&obj, Some("newmtl a\nKd 1 abc 0\n"));
        assert_eq!((path.as_path(), line), (Path::new("m.mtl"), 2));
        assert!(reason.contains("'abc'"), "{reason}");
        let (_, line, reason, _) = parse_error(&obj, Some("newmtl a\n\nKe 1 1\n"));
        assert_eq!(line, 3);
        assert!(reason.contains("expected 3"), "{reason}");
        let (_, _, reason, _) = parse_error(&obj, Some("newmtl a\nTf nan 1 1\n"));
        assert!(reason.contains("non-finite"), "{reason}");
        for bad in ["0", "1.5", "-0.1", "nan"] {
            let (_, line, reason, _) = parse_error(&obj, Some(&format!("newmtl a\nPr {bad}\n")));
            assert_eq!(line, 2);
            assert!(reason.contains("Pr") && reason.contains(bad), "{reason}");
        }
        let (_, _, reason, _) = parse_error(&obj, Some("newmtl a\nNs 1 2\n"));
        assert!(reason.contains("expected 1"), "{reason}");
        let (_, _, reason, _) = parse_error(&obj, Some("newmtl a\nNi 0\n"));
        assert!(reason.contains("positive"), "{reason}");
        let (_, _, reason, _) = parse_error(&obj, Some("newmtl a\nd\n"));
        assert!(reason.contains("expected 1"), "{reason}");
        let (_, _, reason, _) = parse_error(&obj, Some("newmtl a\nKd -1 0 0\n"));
        assert!(reason.contains("negative"), "{reason}");
        let (_, _, reason, _) = parse_error(&obj, Some("newmtl a\nKd spectral x.rfl\n"));
        assert!(reason.contains("not supported"), "{reason}");
    }

    #[test]
    fn unknown_usemtl_lists_the_defined_materials() {
        let obj = format!("mtllib m.mtl\n{SQUARE}usemtl blue\nf 1 2 3\n");
        let (path, line, reason, _) =
            parse_error(&obj, Some("newmtl red\nKd 1 0 0\nnewmtl green\nKd 0 1 0\n"));
        assert_eq!((path.as_path(), line), (Path::new("test.obj"), 6));
        assert!(reason.contains("'blue'"), "{reason}");
        assert!(reason.contains("'red', 'green'"), "{reason}");
        let (_, _, reason, _) = parse_error(&format!("{SQUARE}usemtl red\n"), None);
        assert!(reason.contains("no material library"), "{reason}");
    }

    #[test]
    fn good_file_loads_with_counts_materials_and_normals() {
        let obj = "\
# objects and groups, a face without a material
mtllib m.mtl
o first
v 0 0 0
v 1 0 0   # an inline comment
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 2
vn 0 0 0
s 1
f 1 2 4
usemtl shiny
f 1/1/1 2/2/1 3/3/1 4/4/2
usemtl red
f 1/1/1 3/3/1 4/4/1
o second
v 0 0 1 2
v 1 0 1 0.5 0.5 0.5
v 0 1 1
usemtl red
f 5 6 7
g third
# the material carries over to the next group
f 5 7 6
l 1 2
cstype bezier
";
        let mtl = "\
newmtl red
Kd 0.8 0.1 0.1
newmtl shiny
illum 2
Kd 0.5
Ks 0.2 0.3 0.4
Ka 0.1 0.1 0.1
Ke 0 0 0
Ns 50
Pr 0.25
Ni 1.3
d 1
Tf 0.9 0.8 0.7
map_Ks ignored.png
";
        let data = load_obj_str("good.obj", obj, Some(mtl)).unwrap();
        let mesh = &data.mesh;
        assert_eq!(mesh.faces.len(), 6);
        assert_eq!(mesh.face_materials.len(), 6);
        let names: Vec<&str> = data.materials.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["red", "shiny", "default"]);
        let ids: Vec<u32> = mesh.face_materials.iter().map(|m| m.0).collect();
        assert_eq!(ids, [2, 1, 1, 0, 0, 0]);
        // Normals: one per position, unit length or zero ("use the face normal").
        assert_eq!(mesh.normals.len(), mesh.positions.len());
        assert_eq!(mesh.texcoords.len(), mesh.positions.len());
        for n in &mesh.normals {
            assert!(*n == Vec3::ZERO || (n.length() - 1.0).abs() < 1e-6, "{n}");
        }
        assert!(mesh.normals.contains(&Vec3::Z));
        assert!(mesh.normals.contains(&Vec3::ZERO));
        // w divides the position; vertex colours are dropped.
        assert!(mesh.positions.contains(&Vec3::new(0.0, 0.0, 0.5)));
        assert!(mesh.positions.contains(&Vec3::new(1.0, 0.0, 1.0)));
        for f in 0..mesh.faces.len() {
            assert!(
                mesh.faces[f]
                    .iter()
                    .all(|&i| (i as usize) < mesh.positions.len())
            );
        }
        let shiny = &data.materials[1];
        assert_eq!(shiny.illum, IllumModel::Phong);
        assert_eq!(shiny.diffuse, Vec3::splat(0.5));
        assert_eq!(shiny.specular, Vec3::new(0.2, 0.3, 0.4));
        assert_eq!(shiny.ambient, Vec3::splat(0.1));
        assert_eq!(shiny.shininess, 50.0);
        assert_eq!(shiny.roughness, Some(0.25));
        assert_eq!(shiny.ior, 1.3);
        assert_eq!(shiny.transmission, Vec3::new(0.9, 0.8, 0.7));
        assert!(!shiny.is_emissive());
        let red = &data.materials[0];
        assert_eq!(red.illum, IllumModel::Lambertian);
        assert_eq!((red.ior, red.transmission), (1.0, Vec3::ONE));
        assert_eq!(red.roughness, None);
        assert!(red.diffuse_texture.is_none());
    }

    #[test]
    fn emission_and_defaults_from_mtl() {
        let obj = format!("mtllib m.mtl\n{SQUARE}usemtl lamp\nf 1 2 3\nusemtl plain\nf 1 3 4\n");
        let data = load_obj_str(
            "lamp.obj",
            &obj,
            Some("newmtl lamp\nKe 17 12 4\nKd 0.78 0.78 0.78\nnewmtl plain\n"),
        )
        .unwrap();
        assert_eq!(data.materials.len(), 2);
        assert_eq!(data.materials[0].emission, Vec3::new(17.0, 12.0, 4.0));
        assert!(data.materials[0].is_emissive());
        let plain = &data.materials[1];
        assert_eq!(plain.diffuse, Vec3::splat(0.8));
        assert_eq!(plain.illum, IllumModel::Lambertian);
        assert_eq!(plain.emission, Vec3::ZERO);
    }

    #[test]
    fn objects_without_normals_get_zero_normals_when_merged() {
        let obj = format!("{SQUARE}vn 0 0 1\nf 1 2 3\no plain\nf 1//1 3//1 4//1\n");
        let data = load_obj_str("mixed.obj", &obj, None).unwrap();
        assert_eq!(data.mesh.faces.len(), 2);
        assert_eq!(data.mesh.normals.len(), data.mesh.positions.len());
        assert_eq!(data.mesh.normals[0], Vec3::ZERO);
        assert_eq!(data.mesh.normals[5], Vec3::Z);
        assert!(data.mesh.texcoords.is_empty());
    }

    #[test]
    fn textures_load_relative_to_the_mtl_file() {
        let dir = temp_dir("texture");
        std::fs::create_dir_all(dir.join("mat")).unwrap();
        let mut img = image::RgbImage::new(2, 2);
        img.put_pixel(0, 0, image::Rgb([255, 0, 0]));
        img.save(dir.join("mat/tex.png")).unwrap();
        std::fs::write(
            dir.join("mat/m.mtl"),
            "newmtl a\nmap_Kd tex.png\nnewmtl b\nmap_Kd -s 1 1 1 tex.png\n",
        )
        .unwrap();
        let obj = dir.join("t.obj");
        std::fs::write(
            &obj,
            format!("mtllib mat/m.mtl\n{SQUARE}usemtl a\nf 1 2 3\nusemtl b\nf 1 3 4\n"),
        )
        .unwrap();
        let data = load_obj(&obj).unwrap();
        let a = data.materials[0].diffuse_texture.as_ref().unwrap();
        let b = data.materials[1].diffuse_texture.as_ref().unwrap();
        assert_eq!((a.width, a.height), (2, 2));
        assert!(Arc::ptr_eq(a, b), "the same file is loaded once");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn texture_options_are_parsed_and_those_that_change_the_lookup_refused() {
        for (spec, file) in [
            ("tex.png", "tex.png"),
            ("-s 1 1 1 tex.png", "tex.png"),
            ("-s 1 my texture.png", "my texture.png"),
            (
                "-o 0 0 -blendu off -blendv on -boost 2.5 -clamp off -cc off tex.png",
                "tex.png",
            ),
            ("-mm 0 1 -bm 1 -t 0 tex.png", "tex.png"),
        ] {
            assert_eq!(texture_statement(spec), Ok(file), "{spec}");
        }
        for (spec, expected) in [
            (
                "-s 2 2 1 tex.png",
                "'-s 2 2 1' (a scale of the texture coordinates) is not supported",
            ),
            ("-o 0.5 tex.png", "'-o 0.5' (an offset"),
            ("-clamp on tex.png", "'-clamp on' (clamping"),
            ("-cc on tex.png", "'-cc on'"),
            ("-bm 2 tex.png", "'-bm 2'"),
            ("-imfchan r tex.png", "'-imfchan r'"),
            ("-texres 512 tex.png", "'-texres 512'"),
            ("-mm 0.2 1 tex.png", "'-mm 0.2 1'"),
            (
                "-clamp maybe tex.png",
                "-clamp (clamping of the texture coordinates) is followed by 'maybe'; expected on or off",
            ),
            ("-s tex.png", "expected 1 to 3 finite numbers"),
            ("-halo 1 tex.png", "unknown option '-halo'"),
            ("-s 1 1 1", "without a file name"),
        ] {
            let reason = texture_statement(spec).unwrap_err();
            assert!(reason.contains(expected), "{spec}: {reason}");
        }
        // In an MTL file, with its line.
        let obj = format!("mtllib m.mtl\n{SQUARE}usemtl a\nf 1 2 3\n");
        let (path, line, reason, _) =
            parse_error(&obj, Some("newmtl a\nKd 1 1 1\nmap_Kd -s 2 2 2 tex.png\n"));
        assert_eq!((path.as_path(), line), (Path::new("m.mtl"), 3));
        assert!(reason.contains("'-s 2 2 2'"), "{reason}");
    }

    #[test]
    fn texture_errors_name_the_mtl_line_that_referenced_them() {
        let dir = temp_dir("texture-line");
        std::fs::write(dir.join("bad.png"), b"this is not a PNG file at all").unwrap();
        std::fs::write(
            dir.join("m.mtl"),
            "newmtl a\nKd 1 1 1\n\nnewmtl b\nmap_Kd -s 1 1 1 bad.png\n",
        )
        .unwrap();
        let obj = dir.join("g.obj");
        std::fs::write(&obj, format!("mtllib m.mtl\n{SQUARE}usemtl b\nf 1 2 3\n")).unwrap();
        match load_obj(&obj) {
            Err(e @ Error::Texture { .. }) => {
                let message = e.to_string();
                assert!(
                    message.contains(&format!(
                        "bad.png: cannot read the texture map_Kd of material 'b' at {}:5: the file is not an image raylab reads",
                        dir.join("m.mtl").display()
                    )),
                    "{message}"
                );
            }
            other => panic!("expected a texture error, got {other:?}"),
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn undecodable_texture_is_a_texture_error_naming_it() {
        let dir = temp_dir("garbage");
        std::fs::write(dir.join("garbage.png"), b"this is not a PNG file at all").unwrap();
        std::fs::write(dir.join("m.mtl"), "newmtl a\nmap_Kd garbage.png\n").unwrap();
        let obj = dir.join("g.obj");
        std::fs::write(&obj, format!("mtllib m.mtl\n{SQUARE}usemtl a\nf 1 2 3\n")).unwrap();
        match load_obj(&obj) {
            Err(e @ Error::Texture { .. }) => {
                assert!(e.to_string().contains("garbage.png"), "{e}")
            }
            other => panic!("expected a texture error, got {other:?}"),
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn files_on_disk_load_their_mtl() {
        let dir = temp_dir("disk");
        std::fs::write(
            dir.join("m.mtl"),
            "newmtl a\nKd 0.1 0.2 0.3\nillum 4\nNi 1.5\n",
        )
        .unwrap();
        let obj = dir.join("d.obj");
        std::fs::write(&obj, format!("mtllib m.mtl\n{SQUARE}usemtl a\nf 1 2 3 4\n")).unwrap();
        let data = load_obj(&obj).unwrap();
        assert_eq!(data.mesh.faces.len(), 2);
        assert_eq!(data.materials.len(), 1);
        assert_eq!(data.materials[0].illum, IllumModel::Transparent);
        assert_eq!(data.materials[0].ior, 1.5);
        assert_eq!(data.materials[0].diffuse, Vec3::new(0.1, 0.2, 0.3));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
