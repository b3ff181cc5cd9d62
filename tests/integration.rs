//! The integration tests, one module per file of tests/, compiled into one test binary:
//! each file was a binary of its own, and linking 48 binaries against the whole workspace
//! took most of a cold test build. Run one file's tests by its module name:
//! `cargo test -p glyphcast-cli --test integration material_surfaces::` (the filter is a
//! substring of each test's path, `module::test_name`).
mod common;

mod antialias;
mod architecture;
mod baselines;
mod basis_names;
mod cli;
mod colorbar;
mod compute_figures;
mod compute_path;
mod container;
mod csd_mrtrix;
mod depth_accuracy;
mod elastic;
mod ellipsoid;
mod figures;
mod fit;
mod fit_conventions;
mod frames;
mod fuzz;
mod gpu_eval;
mod hardening;
mod image_write;
mod lighting;
mod material_surfaces;
mod mif;
mod montage;
mod msmt;
mod nifti_input;
mod odf;
mod orientation;
mod outputs;
mod ownership;
mod peaks;
mod pipeline_cache;
mod promotion;
mod proxy;
mod qc;
mod range_inclusion;
mod refusals;
mod render_features;
mod scene_arrays;
mod sh_real_data;
mod sh_render;
mod shadows;
mod sphere;
mod stiffness;
mod tensor_order;
mod tools_folder;
mod tracks;
mod underlay;
mod viewer;
mod viewer_figures;
mod visibility;
mod volume;
mod volume_block;
mod volume_notes;
