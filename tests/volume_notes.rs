//! Small things of issue 26.8: a `--views` montage whose middle slice of one view is
//! empty draws that view at the nearest slice with glyphs (with a note); a 3D file given
//! to `--sh` is refused as not 4D before any question of basis; a 6-volume file given to
//! `--sh` is drawn as band 2 with a note when its name suggests a tensor, and refused
//! when glyphcast's own record says it is one.
use crate::common;
use common::{fresh_dir, glyphcast, text};
use glam::DMat4;
use ndarray::{ArrayD, IxDyn};
use std::path::Path;

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn render(args: &[&str], png: &Path) -> std::process::Output {
    let mut all = vec!["render", "--width", "64", "--height", "64", "-o", text(png)];
    all.extend_from_slice(args);
    glyphcast(&all)
}

#[test]
fn views_skip_an_empty_middle_slice_to_the_nearest_with_glyphs() {
    let dir = fresh_dir("volume-notes-views");
    // Glyphs only at k = 0 and k = 1 of a 4x4x6 volume: the middle axial slice (k = 3)
    // is empty; the middle coronal and sagittal slices cross them.
    let data = ArrayD::from_shape_fn(IxDyn(&[4, 4, 6, 6]), |i| {
        let diagonal = [1.0, 0.0, 0.0, 0.5, 0.0, 0.25][i[3]];
        if i[2] < 2 { diagonal } else { 0.0 }
    });
    let path = dir.join("low.nii");
    common::write_nifti(&path, &data, DMat4::IDENTITY);
    let png = dir.join("views.png");
    let out = render(
        &[
            "--tensor",
            text(&path),
            "--order",
            "2",
            "--tensor-order",
            "glyphcast",
            "--views",
            "axial,coronal,sagittal",
        ],
        &png,
    );
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("the middle axial slice (k=3) holds no glyph; drawn at k=1"),
        "{err}"
    );
    let (w, h, _) = glyphcast::io::png::read_png_rgba8(&png).expect("png");
    assert_eq!((w, h), (3 * 64, 64));
    // The viewer's plan (it builds each panel itself) moves the slice alike.
    let request = glyphcast_dmri::volume::VolumeRequest {
        order: Some(2),
        tensor_order: Some("glyphcast".into()),
        views: Some("axial,coronal".into()),
        ..Default::default()
    };
    let volume = request
        .read_volume(glyphcast_dmri::volume::Coefficients::Tensor, &path)
        .expect("volume");
    let plan = request
        .montage_plan(&volume, glyphcast_dmri::volume::ImageRequest::default())
        .expect("plan");
    assert_eq!(plan.panels[0].slice.index, Some(1));
    assert_eq!(plan.panels[1].slice.index, None);
    assert!(
        plan.notes
            .iter()
            .any(|n| n.to_string().contains("drawn at k=1")),
        "{:?}",
        plan.notes
    );
    // With an index the user named, an empty slice stays an error.
    let out = render(
        &[
            "--tensor",
            text(&path),
            "--order",
            "2",
            "--tensor-order",
            "glyphcast",
            "--views",
            "axial:4,coronal",
        ],
        &dir.join("named.png"),
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stderr(&out).contains("no glyph to draw"));
}

#[test]
fn sh_input_says_what_the_file_is() {
    let dir = fresh_dir("volume-notes-sh");
    let png = dir.join("x.png");
    // 3D: not 4D, said before the basis is asked for.
    let flat = dir.join("flat.nii");
    common::write_nifti(&flat, &ArrayD::ones(IxDyn(&[3, 3, 3])), DMat4::IDENTITY);
    let out = render(&["--sh", text(&flat)], &png);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("flat.nii: dim: a 3D image"), "{err}");
    assert!(!err.contains("basis"), "{err}");
    // Six volumes named like a tensor: drawn as band 2, with a note.
    let six = ArrayD::from_shape_fn(IxDyn(&[3, 3, 1, 6]), |i| {
        [1.0, 0.1, 0.0, 0.2, 0.0, 0.3][i[3]]
    });
    let named = dir.join("sub-01_dti_tensor.nii");
    common::write_nifti(&named, &six, DMat4::IDENTITY);
    let out = render(&["--sh", text(&named), "--basis", "tournier07"], &png);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("note: ")
            && err.contains("its name suggests a diffusion tensor")
            && err.contains("--order 2"),
        "{err}"
    );
    let plain = dir.join("fod.nii");
    common::write_nifti(&plain, &six, DMat4::IDENTITY);
    let out = render(&["--sh", text(&plain), "--basis", "tournier07"], &png);
    assert!(out.status.success());
    assert!(!stderr(&out).contains("note: "), "{}", stderr(&out));
    // glyphcast's own DTI fit given to --sh: refused, naming the record.
    let dti = common::fit_dti_small_64d(&dir);
    let out = render(&["--sh", text(&dti), "--basis", "tournier07"], &png);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("descrip") && err.contains("symmetric tensor of order 2"),
        "{err}"
    );
}

/// A `.mih` whose header ends with the file, without `END` (as MRtrix reads it), reads
/// the same values as the `.mif` it was cut from.
#[test]
fn mih_without_end_reads_as_mrtrix_reads_it() {
    use glyphcast_dmri::io::image::read_image;
    use glyphcast_dmri::io::mif::{MifWrite, write_mif};
    use glyphcast_dmri::io::nifti::{AffineSource, VoxelToWorld};
    let dir = fresh_dir("volume-notes-mih");
    let values = ArrayD::from_shape_fn(IxDyn(&[2, 3, 4, 5]), |i| {
        (i[0] + 10 * i[1] + 100 * i[2] + 1000 * i[3]) as f64
    });
    let map = VoxelToWorld::new(DMat4::IDENTITY, AffineSource::Pixdim, "x", "transform").unwrap();
    let mif = dir.join("full.mif");
    write_mif(
        &mif,
        &MifWrite {
            data: &values,
            voxel_to_world: &map,
            keys: &[],
        },
    )
    .unwrap();
    let bytes = std::fs::read(&mif).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    let file_line = text.lines().find(|l| l.starts_with("file: . ")).unwrap();
    let offset: usize = file_line["file: . ".len()..].parse().unwrap();
    let header_end = text.find(file_line).unwrap();
    let header = format!("{}# written by hand\nfile: data.dat", &text[..header_end]);
    std::fs::write(dir.join("cut.mih"), header).unwrap();
    std::fs::write(dir.join("data.dat"), &bytes[offset..]).unwrap();
    let read = read_image(&dir.join("cut.mih")).expect("a .mih without END");
    assert_eq!(read.data, read_image(&mif).unwrap().data);
    assert_eq!(read.data, values);
}
