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
