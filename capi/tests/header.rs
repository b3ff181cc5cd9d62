//! include/glyphcast.h is what cbindgen makes of capi/src/lib.rs: this test fails when the
//! checked-in header is stale. `GLYPHCAST_BLESS=1 cargo test -p glyphcast-c --test header`
//! rewrites it.
use std::path::Path;

#[test]
fn the_header_is_up_to_date() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config =
        cbindgen::Config::from_file(crate_dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let mut generated = Vec::new();
    cbindgen::Builder::new()
        .with_crate(crate_dir)
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header")
        .write(&mut generated);
    let generated = String::from_utf8(generated).expect("UTF-8");
    let header = crate_dir.join("../include/glyphcast.h");
    if std::env::var("GLYPHCAST_BLESS").is_ok_and(|v| v == "1") {
        std::fs::write(&header, &generated).expect("writing the header");
    }
    let checked_in = std::fs::read_to_string(&header).unwrap_or_default();
    assert!(
        checked_in == generated,
        "include/glyphcast.h is stale: regenerate it with \
         GLYPHCAST_BLESS=1 cargo test -p glyphcast-c --test header"
    );
}

/// The settings struct carries every render setting of the library's table under its key,
/// except those an engine's own frame decides (stated here with the reason): a new
/// render setting fails this test until the C API has it or says why not.
#[test]
fn the_settings_struct_has_every_render_setting() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let header = std::fs::read_to_string(crate_dir.join("../include/glyphcast.h")).unwrap();
    let start = header
        .find("typedef struct GlyphcastSettings {")
        .expect("the settings struct");
    let end = start + header[start..].find("} GlyphcastSettings;").unwrap();
    let fields: Vec<&str> = header[start..end]
        .lines()
        .filter_map(|line| {
            let line = line.trim().strip_suffix(';')?;
            let name = line.split_whitespace().last()?;
            Some(name.split('[').next().unwrap())
        })
        .collect();
    let not_in_c = [
        // The host's colour and depth attachments decide these, not glyphcast.
        ("samples", "the host's attachments' sample count"),
        ("background", "the host clears its own attachments"),
        // A host's pass culls as the default says (early outs, where the device jumps
        // over idle code and the host calls record_compute before its rendering).
        (
            "cull",
            "the engine component draws in one pass of the host's, culled by early outs by default",
        ),
    ];
    for spec in glyphcast::render::table::RENDER_SETTINGS {
        let key = spec.setting.key();
        let excused = not_in_c.iter().any(|(k, _)| *k == key);
        assert!(
            fields.contains(&key) != excused,
            "{key}: in the struct {}, excused {excused}",
            fields.contains(&key)
        );
    }
}
