//! Which shaderc the `shaderc-sys` crate links, whether it is complete, and what
//! completes it: shared by the build script (which prints the plan) and the unit tests.

use object::read::elf::{Dyn, FileHeader};
use object::{FileKind, Object, ObjectSymbol};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The static libraries of glslang and SPIRV-Tools that hold what a split shaderc leaves
/// undefined, in link order; `true`: required (glslang 14 and later merge the others
/// into libglslang.a, so those are taken where they exist).
pub const PARTS: [(&str, bool); 8] = [
    ("glslang", true),
    ("SPIRV", false),
    ("MachineIndependent", false),
    ("GenericCodeGen", false),
    ("OSDependent", false),
    ("OGLCompiler", false),
    ("SPIRV-Tools-opt", true),
    ("SPIRV-Tools", true),
];

/// What to install, for every message that stops the build.
pub const INSTALL: &str = "Install a complete shaderc: on Debian 12, `apt install libshaderc-dev \
    glslang-dev spirv-tools` (its static shaderc is completed here with glslang's and \
    SPIRV-Tools' static libraries); on Debian 13 and Ubuntu 24.04, `apt install \
    libshaderc-dev`; on Fedora, `dnf install libshaderc-devel`; on Arch, `pacman -S \
    shaderc`; or set VULKAN_SDK to an installed Vulkan SDK, or SHADERC_LIB_DIR to a \
    folder holding a complete libshaderc.so or libshaderc_combined.a.";

/// The folder shaderc-sys searches when neither SHADERC_LIB_DIR nor VULKAN_SDK is set
/// and pkg-config does not know `shaderc`, for a Linux target of `arch`
/// (`CARGO_CFG_TARGET_ARCH`).
pub fn system_dir(arch: &str) -> PathBuf {
    let debian_arch = if arch == "x86" { "i386" } else { arch };
    let multiarch = PathBuf::from(format!("/usr/lib/{debian_arch}-linux-gnu/"));
    if multiarch.exists() {
        multiarch
    } else if arch == "x86_64" && Path::new("/usr/lib64/").exists() {
        PathBuf::from("/usr/lib64/")
    } else {
        PathBuf::from("/usr/lib/")
    }
}

/// Whether a symbol name is glslang's or SPIRV-Tools' (C++ names, mangled).
fn is_compiler_symbol(name: &str) -> bool {
    name.contains("glslang") || name.contains("spvtools")
}

/// The names of `data`'s (an ELF shared library's) dynamic symbols: undefined ones if
/// `undefined`, else defined ones.
fn dynamic_symbols(data: &[u8], undefined: bool) -> Result<BTreeSet<String>, String> {
    let file = object::File::parse(data).map_err(|e| e.to_string())?;
    Ok(file
        .dynamic_symbols()
        .filter(|symbol| symbol.is_undefined() == undefined)
        .filter_map(|symbol| symbol.name().ok().map(str::to_owned))
        .collect())
}

/// The DT_NEEDED entries of an ELF shared library.
fn needed(data: &[u8]) -> Result<Vec<String>, String> {
    match FileKind::parse(data).map_err(|e| e.to_string())? {
        FileKind::Elf32 => needed_of::<object::elf::FileHeader32<object::Endianness>>(data),
        FileKind::Elf64 => needed_of::<object::elf::FileHeader64<object::Endianness>>(data),
        kind => Err(format!("not an ELF file ({kind:?})")),
    }
}

fn needed_of<Elf: FileHeader<Endian = object::Endianness>>(
    data: &[u8],
) -> Result<Vec<String>, String> {
    let header = Elf::parse(data).map_err(|e| e.to_string())?;
    let endian = header.endian().map_err(|e| e.to_string())?;
    let sections = header.sections(endian, data).map_err(|e| e.to_string())?;
    let Some((entries, link)) = sections.dynamic(endian, data).map_err(|e| e.to_string())? else {
        return Ok(Vec::new());
    };
    let strings = sections
        .strings(endian, data, link)
        .map_err(|e| e.to_string())?;
    Ok(entries
        .iter()
        .filter(|entry| entry.d_tag(endian).into() == object::elf::DT_NEEDED)
        .filter_map(|entry| entry.string(endian, strings).ok())
        .map(|name| String::from_utf8_lossy(name).into_owned())
        .collect())
}

/// glslang's TProgram constructor: what a complete static shaderc defines and Debian's
/// `libshaderc_combined.a` (shaderc's own code alone) does not.
const GLSLANG_MARKER: &str = "_ZN7glslang8TProgramC1Ev";

/// Whether the static archive `path` defines glslang (its symbol index names
/// [`GLSLANG_MARKER`]).
pub fn archive_has_glslang(path: &Path) -> Result<bool, String> {
    let data = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let archive = object::read::archive::ArchiveFile::parse(&*data)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let Some(symbols) = archive
        .symbols()
        .map_err(|e| format!("{}: {e}", path.display()))?
    else {
        return Ok(false);
    };
    Ok(symbols
        .filter_map(Result::ok)
        .any(|symbol| symbol.name() == GLSLANG_MARKER.as_bytes()))
}

/// The DT_NEEDED libraries of the shared library `library` (found in `dir`) that define
/// some of its glslang and SPIRV-Tools symbols, and those symbols that none defines.
pub fn providers(library: &Path, dir: &Path) -> Result<(Vec<String>, BTreeSet<String>), String> {
    let read = |path: &Path| std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()));
    let data = read(library)?;
    let mut missing: BTreeSet<String> = dynamic_symbols(&data, true)
        .map_err(|e| format!("{}: {e}", library.display()))?
        .into_iter()
        .filter(|name| is_compiler_symbol(name))
        .collect();
    let mut found = Vec::new();
    for name in needed(&data).map_err(|e| format!("{}: {e}", library.display()))? {
        if missing.is_empty() {
            break;
        }
        let path = dir.join(&name);
        if let Ok(data) = std::fs::read(&path) {
            let defined =
                dynamic_symbols(&data, false).map_err(|e| format!("{}: {e}", path.display()))?;
            let before = missing.len();
            missing.retain(|symbol| !defined.contains(symbol));
            if missing.len() < before {
                found.push(name);
            }
        }
    }
    Ok((found, missing))
}

/// glslang's and SPIRV-Tools' symbols that the shared library `library` leaves undefined
/// and that none of its DT_NEEDED libraries found in `dir` defines: empty for a
/// complete shaderc (one that holds glslang, or links a shared glslang), not for
/// Debian 12's.
pub fn unresolved(library: &Path, dir: &Path) -> Result<BTreeSet<String>, String> {
    providers(library, dir).map(|(_, missing)| missing)
}

/// What shaderc-sys (with its `prefer-static-linking` feature, which this crate turns
/// on) links from `dir`, and what completes it.
#[derive(Debug, PartialEq)]
pub enum Plan {
    /// A complete shaderc, or none (then shaderc-sys builds its own from source): the
    /// build script adds nothing.
    Nothing,
    /// A static shaderc without glslang, completed by the shared libraries that the
    /// system's libshaderc.so links (Debian 13, Ubuntu 24.04): their file names.
    Shared(Vec<String>),
    /// A static shaderc without glslang, completed by the static glslang and
    /// SPIRV-Tools libraries of the same folder (Debian 12): their `PARTS` names.
    Static(Vec<&'static str>),
}

impl Plan {
    /// The build script's `cargo:` lines for this plan, in `dir`.
    pub fn lines(&self, dir: &Path) -> Vec<String> {
        let libraries: Vec<String> = match self {
            Plan::Nothing => return Vec::new(),
            Plan::Shared(names) => names
                .iter()
                .map(|name| format!("dylib:+verbatim={name}"))
                .collect(),
            Plan::Static(parts) => parts
                .iter()
                .map(|part| format!("static:-bundle={part}"))
                .collect(),
        };
        let mut lines = vec![format!("cargo:rustc-link-search=native={}", dir.display())];
        lines.extend(
            libraries
                .iter()
                .map(|library| format!("cargo:rustc-link-lib={library}")),
        );
        // glslang and SPIRV-Tools are C++.
        lines.push("cargo:rustc-link-lib=dylib=stdc++".to_owned());
        lines
    }
}

/// The plan for the shaderc that shaderc-sys finds in `dir`, or the paragraph that stops
/// the build.
pub fn plan(dir: &Path) -> Result<Plan, String> {
    let shared = ["libshaderc.so", "libshaderc_shared.so"]
        .iter()
        .map(|name| dir.join(name))
        .find(|path| path.exists());
    let combined = dir.join("libshaderc_combined.a");
    if !combined.exists() {
        // The shared library, or none (shaderc-sys's build from source).
        let Some(shared) = shared else {
            return Ok(Plan::Nothing);
        };
        let missing = unresolved(&shared, dir)?;
        if missing.is_empty() {
            return Ok(Plan::Nothing);
        }
        return Err(format!(
            "{} is split: it leaves {} of glslang's and SPIRV-Tools' symbols undefined (as \
             Debian 12's does), and the static shaderc (libshaderc_combined.a) that could be \
             linked in its place is not in {}. {INSTALL}",
            shared.display(),
            missing.len(),
            dir.display()
        ));
    }
    if archive_has_glslang(&combined)? {
        return Ok(Plan::Nothing);
    }
    // The shared libraries that complete the system's libshaderc.so complete its static
    // archive too (the same code).
    if let Some(shared) = &shared {
        let (found, missing) = providers(shared, dir)?;
        if missing.is_empty() && !found.is_empty() {
            return Ok(Plan::Shared(found));
        }
    }
    let absent: Vec<String> = PARTS
        .iter()
        .filter(|(part, required)| *required && !dir.join(format!("lib{part}.a")).exists())
        .map(|(part, _)| format!("lib{part}.a"))
        .collect();
    if !absent.is_empty() {
        return Err(format!(
            "{} holds shaderc without glslang and SPIRV-Tools (as Debian 12's does), and \
             the static libraries that complete it are not in {} (missing: {}). {INSTALL}",
            combined.display(),
            dir.display(),
            absent.join(", ")
        ));
    }
    Ok(Plan::Static(
        PARTS
            .iter()
            .map(|(part, _)| *part)
            .filter(|part| dir.join(format!("lib{part}.a")).exists())
            .collect(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A new empty folder under the target folder's temporary space.
    fn folder(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "glyphcast-shaderc-link-{}-{name}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// Debian 12's shared shaderc, where this is Debian 12 with libshaderc-dev.
    fn debian12_shaderc() -> Option<PathBuf> {
        let version = std::fs::read_to_string("/etc/debian_version").ok()?;
        let dir = system_dir(std::env::consts::ARCH);
        let library = dir.join("libshaderc.so");
        (version.starts_with("12") && library.exists()).then_some(dir)
    }

    fn names_packages(message: &str) {
        for package in [
            "libshaderc-dev glslang-dev spirv-tools",
            "libshaderc-devel",
            "pacman -S",
            "VULKAN_SDK",
        ] {
            assert!(
                message.contains(package),
                "{package} is not named: {message}"
            );
        }
    }

    #[test]
    fn no_shaderc_is_left_to_shaderc_sys() {
        // shaderc-sys builds its own from source (or stops, naming CMake) before this.
        assert_eq!(plan(&folder("empty")), Ok(Plan::Nothing));
    }

    #[test]
    fn a_complete_shared_shaderc_adds_nothing() {
        // An ELF shared object whose undefined symbols are no glslang's: this test
        // program (a position-independent executable) stands in for a complete shaderc.
        let dir = folder("complete");
        std::fs::copy(std::env::current_exe().unwrap(), dir.join("libshaderc.so")).unwrap();
        assert_eq!(plan(&dir), Ok(Plan::Nothing));
        assert_eq!(Plan::Nothing.lines(&dir), Vec::<String>::new());
    }

    #[test]
    fn a_split_shaderc_without_its_parts_names_the_packages() {
        // A static shaderc whose symbol index lacks glslang, alone in its folder.
        let dir = folder("static");
        std::fs::write(dir.join("libshaderc_combined.a"), b"!<arch>\n").unwrap();
        let message = plan(&dir).unwrap_err();
        assert!(message.contains("libglslang.a"), "{message}");
        names_packages(&message);
    }

    #[test]
    fn debian12_shaderc_is_completed_from_its_archives() {
        let Some(system) = debian12_shaderc() else {
            eprintln!("skipped: not Debian 12 with libshaderc-dev");
            return;
        };
        let library = system.join("libshaderc.so");
        let (found, missing) = providers(&library, &system).unwrap();
        assert!(found.is_empty(), "{found:?}");
        assert!(missing.len() > 30, "{missing:?}");
        assert!(missing.contains("_ZN7glslang8TProgramC1Ev"), "{missing:?}");
        assert!(!archive_has_glslang(&system.join("libshaderc_combined.a")).unwrap());
        // glslang 12 defines its core in MachineIndependent (libglslang.a is a stub).
        assert!(archive_has_glslang(&system.join("libMachineIndependent.a")).unwrap());
        // Its own folder holds the archives (glslang-dev, spirv-tools installed).
        let plan = plan(&system).unwrap();
        let Plan::Static(parts) = &plan else {
            panic!("{plan:?}")
        };
        assert_eq!(parts.len(), PARTS.len(), "{parts:?}");
        let lines = plan.lines(&system);
        let search = format!("cargo:rustc-link-search=native={}", system.display());
        assert_eq!(lines.first(), Some(&search));
        assert!(lines.contains(&"cargo:rustc-link-lib=static:-bundle=glslang".to_owned()));
        // The shared library alone in a folder: split, and the message names the packages.
        let dir = folder("split");
        std::os::unix::fs::symlink(&library, dir.join("libshaderc.so")).unwrap();
        let message = plan_of(&dir);
        assert!(message.contains("is split"), "{message}");
        names_packages(&message);
    }

    fn plan_of(dir: &Path) -> String {
        plan(dir).unwrap_err()
    }
}
