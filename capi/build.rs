//! Gives libglyphcast_c.so a versioned SONAME, `libglyphcast_c.so.<ABI>`, so that a
//! program linked against it records the ABI it was built for (the ABI is the major
//! version, or major.minor while the major is 0, as semver breaks there). rustc sets no
//! SONAME on a cdylib by itself. tools/install-c.sh installs the file under that name
//! with the unversioned name linking to it.
fn main() {
    let major = std::env::var("CARGO_PKG_VERSION_MAJOR").unwrap_or_default();
    let minor = std::env::var("CARGO_PKG_VERSION_MINOR").unwrap_or_default();
    let abi = if major == "0" {
        format!("0.{minor}")
    } else {
        major
    };
    if std::env::var("CARGO_CFG_TARGET_OS").is_ok_and(|os| os == "linux") {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,libglyphcast_c.so.{abi}");
    }
    println!("cargo:rerun-if-changed=build.rs");
}
