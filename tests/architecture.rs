//! The layering rules of docs/architecture.md, read from the sources: a module may
//! import only the layers below it. Each rule names the folder and the modules it must
//! not reach; a `crate::NAME` path anywhere in the folder's files (a `use`, a path in
//! code, a grouped `use crate::{NAME, ...}`) breaks it.
use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

/// Every `.rs` file below `dir`.
fn sources(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The top-level modules a source names through `crate::`, with the line of each:
/// `crate::scene::X` gives `scene`, `crate::{scene, Error}` gives `scene` and `Error`.
fn crate_modules(text: &str) -> Vec<(usize, String)> {
    let mut found = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(at) = rest.find("crate::") {
            let start = &rest[at + "crate::".len()..];
            if let Some(group) = start.strip_prefix('{') {
                // A grouped import: the top-level names up to the matching brace (one
                // line is enough here: the grouped imports of a module's root names).
                let mut depth = 0;
                let mut name = String::new();
                for c in group.chars() {
                    match c {
                        '{' => depth += 1,
                        '}' if depth == 0 => break,
                        '}' => depth -= 1,
                        ',' if depth == 0 => {
                            found.push((number + 1, std::mem::take(&mut name)));
                        }
                        c if depth == 0 && (is_ident(c) || c == ':') => name.push(c),
                        _ => {}
                    }
                }
                found.push((number + 1, name));
            } else {
                let name: String = start.chars().take_while(|&c| is_ident(c)).collect();
                found.push((number + 1, name));
            }
            rest = start;
        }
    }
    found
        .into_iter()
        .map(|(line, path)| (line, path.split("::").next().unwrap_or("").to_string()))
        .filter(|(_, name)| !name.is_empty())
        .collect()
}

/// The places below `folder` that reach one of `forbidden`.
fn violations(folder: &str, forbidden: &[&str]) -> Vec<String> {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let mut found = Vec::new();
    for file in sources(&root.join(folder)) {
        let text = fs::read_to_string(&file).unwrap();
        for (line, name) in crate_modules(&text) {
            if forbidden.contains(&name.as_str()) {
                let shown = file.strip_prefix(root).unwrap().display();
                found.push(format!("{shown}:{line} imports crate::{name}"));
            }
        }
    }
    found
}

#[test]
fn the_reader_finds_grouped_and_nested_paths() {
    let text = "use crate::{scene::ShBasis, Error};\nlet x = crate::fit::f(); // crate::io\n";
    let names: BTreeSet<String> = crate_modules(text).into_iter().map(|(_, n)| n).collect();
    let expected: BTreeSet<String> = ["scene", "Error", "fit"].map(String::from).into();
    assert_eq!(names, expected);
}

/// The float64 mathematics sits below the domain model, the volumes, the passes and the
/// file formats.
#[test]
fn glyph_imports_no_higher_layer() {
    let found = violations("src/glyph", &["scene", "volume", "fit", "render", "io"]);
    assert!(found.is_empty(), "{}", found.join("\n"));
}

/// `fit` writes volumes that `volume` reads: `fit` may use `volume`, never the reverse.
#[test]
fn volume_does_not_import_fit() {
    let found = violations("crates/glyphcast-dmri/src/volume", &["fit", "qc"]);
    assert!(found.is_empty(), "{}", found.join("\n"));
}

/// The source folders of the workspace's Rust crates: the core's `src/`, each member's
/// under `crates/`, the Python module's and the C API's.
fn crate_sources(root: &Path) -> Vec<PathBuf> {
    let mut dirs = vec![root.join("src")];
    let mut members: Vec<PathBuf> = fs::read_dir(root.join("crates"))
        .unwrap()
        .map(|entry| entry.unwrap().path().join("src"))
        .collect();
    members.sort();
    dirs.extend(members);
    dirs.extend([root.join("python/src"), root.join("capi/src")]);
    dirs
}

/// The code of every library source of the workspace (comments, the trailing
/// `#[cfg(test)] mod tests` and the test modules' own files left out), with its path.
fn library_code() -> Vec<(String, Vec<(usize, String)>)> {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    crate_sources(root)
        .iter()
        .flat_map(|dir| sources(dir))
        .filter(|file| {
            let is_tests = |part: &std::ffi::OsStr| part == "tests" || part == "tests.rs";
            !file.strip_prefix(root).unwrap().iter().any(is_tests)
        })
        .map(|file| {
            let text = fs::read_to_string(&file).unwrap();
            let library = text.split("#[cfg(test)]\nmod tests").next().unwrap_or("");
            let lines = library
                .lines()
                .enumerate()
                .map(|(n, line)| (n + 1, line.split("//").next().unwrap_or("").to_string()))
                .collect();
            let shown = file.strip_prefix(root).unwrap().display().to_string();
            (shown, lines)
        })
        .collect()
}

/// The code lines of the library that contain `needle`.
fn code_lines_with(needle: &str) -> Vec<String> {
    let mut found = Vec::new();
    for (file, lines) in library_code() {
        for (number, code) in lines {
            if code.contains(needle) {
                found.push(format!("{file}:{number}: {}", code.trim()));
            }
        }
    }
    found
}

/// The largest image side is one constant, `scene::MAX_IMAGE_SIDE`; every check names it.
#[test]
fn largest_image_side_is_written_once() {
    let found = code_lines_with("16384");
    assert_eq!(found.len(), 1, "{}", found.join("\n"));
    assert!(found[0].starts_with("src/scene.rs"), "{}", found[0]);
}

/// The device's limits are read once, into `DeviceContext`; everything else asks it.
#[test]
fn device_limits_are_read_in_the_device_context() {
    let found: Vec<String> = code_lines_with(".limits")
        .into_iter()
        .filter(|line| !line.starts_with("src/vk/context.rs"))
        .collect();
    assert!(found.is_empty(), "{}", found.join("\n"));
}

/// `build.rs` stays a short main over the manifest (`build/manifest.rs`) and the
/// generator (`build/table.rs`): the table's formatting lives in the generator.
#[test]
fn build_script_main_is_short() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let text = fs::read_to_string(root.join("build.rs")).unwrap();
    let start = text.find("\nfn main() {").expect("build.rs has a main");
    let body = &text[start + 1..];
    let end = body
        .find("\n}\n")
        .expect("main ends with a closing brace at column 0");
    let lines = body[..end].lines().count() + 1;
    assert!(lines <= 60, "build.rs main is {lines} lines, at most 60");
}

/// The embedding examples compile their own shaders: no example shader in the library's
/// shader table, nor in the library.
#[test]
fn library_shader_table_has_no_example_shaders() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let mut files = sources(&root.join("build"));
    files.push(root.join("build.rs"));
    files.extend(sources(&root.join("src")));
    for file in files {
        let text = fs::read_to_string(&file).unwrap().to_ascii_lowercase();
        assert!(
            !text.contains("example_plane") && !text.contains("examples/shaders"),
            "{} builds or names an example's shader",
            file.display()
        );
    }
    let glsl: Vec<String> = fs::read_dir(root.join("glsl"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.starts_with("example"))
        .collect();
    assert!(glsl.is_empty(), "example shaders in glsl/: {glsl:?}");
}

/// `render/` holds the GPU passes (and supersampling's box filter, which the headless
/// renderer applies); the CPU compositing of their images lives in `render/compose/`
/// and the doc-hidden GLSL harnesses in `render/harness/`.
#[test]
fn render_keeps_each_kind_in_its_folder() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("src/render");
    for (folder, files) in [
        ("compose", &["colorbar", "figure", "labels", "montage"][..]),
        ("harness", &["eval", "range_eval"][..]),
    ] {
        for name in files {
            let file = format!("{name}.rs");
            assert!(root.join(folder).join(&file).is_file(), "{folder}/{file}");
            assert!(
                !root.join(&file).exists(),
                "render/{file} belongs in {folder}/"
            );
        }
    }
}

/// The colour bar is made from glyphs in one place (`ColorBar::of_glyphs`); only the
/// viewer, which knows its panel's extent, calls `of_magnitude` itself.
#[test]
fn the_colour_bar_is_made_in_one_place() {
    let found: Vec<String> = code_lines_with("ColorBar::of_magnitude(")
        .into_iter()
        .chain(code_lines_with(".append(&image.rgba"))
        .filter(|line| !line.starts_with("src/render/compose/colorbar.rs"))
        .collect();
    assert!(found.len() <= 1, "{}", found.join("\n"));
    assert!(
        found
            .iter()
            .all(|l| l.starts_with("crates/glyphcast-viewer/src/")),
        "{}",
        found.join("\n")
    );
}

/// One figure sequence: the CLI, Python and the viewer draw a view's frame and its
/// labels, caption and colour bar through `render::compose::figure`; only it (and the
/// montage it serves) draws the frame for a figure and puts anything over or beside it.
/// The accuracy report draws frames to measure them, not figures.
#[test]
fn figures_are_drawn_by_one_sequence() {
    let found: Vec<String> = [
        ".render_view(",
        "draw_edge_labels(",
        "draw_caption(",
        ".append_to(",
        "ColorBar::of_glyphs(",
    ]
    .iter()
    .flat_map(|needle| code_lines_with(needle))
    .filter(|line| !line.starts_with("src/render/compose/"))
    .filter(|line| !line.starts_with("src/accuracy/"))
    .collect();
    assert!(found.is_empty(), "{}", found.join("\n"));
    for front_end in [
        "crates/glyphcast-cli/src/cli/render.rs",
        "python/src/renderer.rs",
        "crates/glyphcast-viewer/src/figure.rs",
    ] {
        let calls = library_code()
            .into_iter()
            .filter(|(file, _)| file == front_end)
            .flat_map(|(_, lines)| lines)
            .filter(|(_, code)| code.contains("_figure("))
            .count();
        assert!(calls > 0, "{front_end} calls no figure sequence");
    }
}

/// `missing_docs` holds in every library crate: each warns on it unconditionally (not
/// under a `cfg_attr` of some feature), and CI lints the whole workspace with all
/// features on, warnings denied.
#[test]
fn missing_docs_holds_in_every_library_crate() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    // The Python module's documentation is its docstrings.
    for dir in crate_sources(root)
        .into_iter()
        .filter(|d| !d.ends_with("python/src"))
    {
        let Some(crate_root) = ["lib.rs"].iter().map(|f| dir.join(f)).find(|f| f.is_file()) else {
            continue;
        };
        let text = fs::read_to_string(&crate_root).unwrap();
        assert!(
            text.lines().any(|l| l.trim() == "#![warn(missing_docs)]"),
            "{} must warn on missing docs",
            crate_root.display()
        );
    }
    let ci = fs::read_to_string(root.join(".ci/run")).unwrap();
    assert!(
        ci.lines().any(|l| l.starts_with("cargo clippy")
            && l.contains("--workspace")
            && l.contains("--all-features")
            && l.contains("-D warnings")),
        ".ci/run has no clippy run over the workspace with --all-features and -D warnings"
    );
}

/// The fits' constraint and search directions come from one place: the hemisphere of
/// a geodesic sphere is taken by `GeodesicSphere::hemisphere`, not filtered again by
/// each fitter.
#[test]
fn the_geodesic_hemisphere_is_taken_in_one_place() {
    let found = code_lines_with("(v.z, v.y, v.x) >");
    assert_eq!(found.len(), 1, "{}", found.join("\n"));
    assert!(
        found[0].starts_with("crates/glyphcast-dmri/src/fit/sphere.rs"),
        "{}",
        found[0]
    );
}

/// The error variants whose payload is essentially prose written at the call site:
/// `Flag` (a front end's own option with its message). `Unsupported` names what was
/// asked for with `error::Asked`, and the untyped `Invalid(String)`/`Usage(String)` are
/// gone (`errors_have_no_bare_sentence_variant` keeps them out).
const STRING_CARRYING: &[&str] = &["Error::Flag {"];

/// The constructions of string-carrying variants left in library code (the command line
/// included), outside tests. Issue 27 asks for at most 15; it may only fall.
const MOST_STRING_ERRORS: usize = 3;

/// No variant of the library's error is a bare sentence (`Invalid(String)`), and no code
/// turns one kind of error into a usage error after the fact (`into_usage`): the exit
/// code follows from the variant (`Error::is_usage`).
#[test]
fn errors_have_no_bare_sentence_variant() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let text = fs::read_to_string(root.join("src/error.rs")).unwrap();
    let bare: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|line| {
            line.ends_with("(String),")
                && line.chars().next().is_some_and(|c| c.is_ascii_uppercase())
        })
        .collect();
    assert!(bare.is_empty(), "variants carrying a bare String: {bare:?}");
    let converted = code_lines_with("into_usage");
    assert!(converted.is_empty(), "{}", converted.join("\n"));
}

/// Errors are typed: few string-carrying variants are built, and no code turns a match
/// arm into one (`Error::Flag { .. }` in a pattern is fine, a construction is counted).
#[test]
fn string_carrying_errors_stay_few() {
    let mut built = Vec::new();
    for needle in STRING_CARRYING {
        built.extend(
            code_lines_with(needle)
                .into_iter()
                .filter(|line| !line.contains(&format!("{needle}_)")) && !line.contains("=>"))
                .filter(|line| !line.starts_with("src/error.rs")),
        );
    }
    assert!(
        built.len() <= MOST_STRING_ERRORS,
        "{} constructions of string-carrying errors (at most {MOST_STRING_ERRORS}):\n{}",
        built.len(),
        built.join("\n")
    );
}

/// No setting is parsed back out of a message: no control-character markers (U+001F,
/// U+001E) and no `mention`/`spell_mentions` in the library, the Python module or the C
/// API; settings travel as typed fields or `Message` pieces.
#[test]
fn no_setting_is_parsed_out_of_a_message() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let mut found = Vec::new();
    for dir in crate_sources(root) {
        for file in sources(&dir) {
            let text = fs::read_to_string(&file).unwrap();
            for (number, line) in text.lines().enumerate() {
                let marker = ["\\u{1f}", "\\u{1e}", "\u{1f}", "\u{1e}"]
                    .iter()
                    .any(|m| line.contains(m));
                let parsing = [".mention()", "spell_mentions", "spell_settings"]
                    .iter()
                    .any(|m| line.contains(m));
                if marker || parsing {
                    let shown = file.strip_prefix(root).unwrap().display();
                    found.push(format!("{shown}:{}: {}", number + 1, line.trim()));
                }
            }
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}

/// A source's module path below its crate's `src/`: `render/compose/montage.rs` is
/// `[render, compose, montage]`; `mod.rs`, `lib.rs` and `main.rs` stand for their folder.
fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let mut parts: Vec<String> = file
        .strip_prefix(src)
        .unwrap()
        .with_extension("")
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    if parts
        .last()
        .is_some_and(|p| ["mod", "lib", "main"].contains(&p.as_str()))
    {
        parts.pop();
    }
    parts
}

/// The module paths a line of code names through `crate::` or `super::` (relative to
/// `module`), grouped imports expanded one level: `use crate::a::{b, c::d}` names
/// `a::b` and `a::c::d`.
fn named_paths(module: &[String], code: &str) -> Vec<Vec<String>> {
    let mut found = Vec::new();
    for (prefix, base) in [
        ("crate::", Vec::new()),
        ("super::", module[..module.len().saturating_sub(1)].to_vec()),
    ] {
        let mut rest = code;
        while let Some(at) = rest.find(prefix) {
            let preceded = rest[..at].chars().next_back().is_some_and(is_ident);
            rest = &rest[at + prefix.len()..];
            if preceded {
                continue;
            }
            let head: String = rest
                .chars()
                .take_while(|&c| is_ident(c) || c == ':')
                .collect();
            let mut path = base.clone();
            path.extend(head.split("::").filter(|s| !s.is_empty()).map(String::from));
            match rest[head.len()..].strip_prefix('{') {
                Some(group) => {
                    let group = group.split('}').next().unwrap_or("");
                    for item in group.split(',') {
                        let mut item_path = path.clone();
                        item_path.extend(
                            item.trim()
                                .split("::")
                                .filter(|s| !s.is_empty() && s.chars().all(is_ident))
                                .map(String::from),
                        );
                        found.push(item_path);
                    }
                }
                None => found.push(path),
            }
        }
    }
    found
}

/// The import circles of the crate whose sources are in `src`: at each depth of the
/// module tree, modules are taken whole (their submodules' imports with them), and an
/// import between a module and its own ancestor or descendant does not count (a module
/// declares its children and they use its items). Each circle is listed by its modules.
fn import_circles(src: &Path) -> Vec<Vec<String>> {
    let mut modules: BTreeSet<Vec<String>> = BTreeSet::new();
    let mut code: Vec<(Vec<String>, String)> = Vec::new();
    for file in sources(src) {
        let path = module_path(src, &file);
        if path.iter().any(|p| p == "tests") {
            continue;
        }
        let text = fs::read_to_string(&file).unwrap();
        let library = text.split("#[cfg(test)]").next().unwrap_or("").to_string();
        modules.insert(path.clone());
        code.push((path, library));
    }
    // The module an imported path lands in: its longest prefix that is a module.
    let resolve = |path: &[String]| -> Option<Vec<String>> {
        (1..=path.len())
            .rev()
            .map(|k| path[..k].to_vec())
            .find(|prefix| modules.contains(prefix))
    };
    let mut edges: BTreeSet<(Vec<String>, Vec<String>)> = BTreeSet::new();
    for (module, text) in &code {
        for line in text.lines() {
            let line = line.split("//").next().unwrap_or("");
            for path in named_paths(module, line) {
                if let Some(target) = resolve(&path) {
                    edges.insert((module.clone(), target));
                }
            }
        }
    }
    let depth = modules.iter().map(Vec::len).max().unwrap_or(0);
    let mut circles = Vec::new();
    for level in 1..=depth {
        let cut = |m: &Vec<String>| m[..m.len().min(level)].to_vec();
        let mut graph: std::collections::BTreeMap<Vec<String>, BTreeSet<Vec<String>>> =
            Default::default();
        for (from, to) in &edges {
            let (a, b) = (cut(from), cut(to));
            let nested = a.starts_with(&b) || b.starts_with(&a);
            if !nested {
                graph.entry(a).or_default().insert(b);
            }
        }
        // A circle: a module that reaches itself. Each strongly connected set once.
        let reach = |start: &Vec<String>| {
            let mut seen = BTreeSet::new();
            let mut stack = vec![start.clone()];
            while let Some(m) = stack.pop() {
                for next in graph.get(&m).into_iter().flatten() {
                    if seen.insert(next.clone()) {
                        stack.push(next.clone());
                    }
                }
            }
            seen
        };
        let mut listed: BTreeSet<Vec<String>> = BTreeSet::new();
        for module in graph.keys() {
            if listed.contains(module) {
                continue;
            }
            let from = reach(module);
            if !from.contains(module) {
                continue;
            }
            let circle: Vec<Vec<String>> = from
                .into_iter()
                .filter(|other| reach(other).contains(module))
                .collect();
            listed.extend(circle.iter().cloned());
            circles.push(circle.iter().map(|m| m.join("/")).collect());
        }
    }
    circles
}

#[test]
fn the_circle_finder_sees_circles_through_groups_and_super() {
    let dir = std::env::temp_dir().join(format!("glyphcast-circles-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(dir.join("a")).unwrap();
    fs::write(dir.join("lib.rs"), "pub mod a;\npub mod b;\n").unwrap();
    fs::write(
        dir.join("a/mod.rs"),
        "pub mod x;\npub mod y;\nuse crate::b::B;\n",
    )
    .unwrap();
    fs::write(dir.join("a/x.rs"), "use super::y::Y;\n").unwrap();
    fs::write(dir.join("a/y.rs"), "use super::{x::X, super::b};\n").unwrap();
    fs::write(dir.join("b.rs"), "use crate::{a::x::X};\n").unwrap();
    let circles = import_circles(&dir);
    fs::remove_dir_all(&dir).unwrap();
    assert_eq!(
        circles,
        vec![
            vec!["a".to_string(), "b".to_string()],
            vec!["a/x".into(), "a/y".into()]
        ]
    );
}

/// No crate of the workspace has an import circle at any depth of its module tree
/// (error types below everything, the Vulkan layer below render and io, one file of a
/// folder above or below its siblings, never both).
#[test]
fn no_crate_has_an_import_circle() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let mut found = Vec::new();
    for src in crate_sources(root) {
        for circle in import_circles(&src) {
            let shown = src.strip_prefix(root).unwrap().display().to_string();
            found.push(format!("{shown}: {}", circle.join(" <-> ")));
        }
    }
    assert!(found.is_empty(), "import circles:\n{}", found.join("\n"));
}
