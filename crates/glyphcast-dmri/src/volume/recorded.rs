//! The SH basis a coefficient file records, and how it meets `--basis`; the same for
//! the stored order of a tensor file's entries and `--tensor-order`.
//!
//! glyphcast's `fit` writes its model into the file's description (NIfTI `descrip`,
//! MRtrix `comments`): "glyphcast fit: SH band 8 descoteaux07 legacy lambda 0.006"
//! (`fit::FitModel::description`); the basis is read back from there. MRtrix
//! itself records no basis: its SH images are always tournier07 (non-legacy), so an
//! MRtrix file that records nothing is taken as that. A NIfTI file that records nothing
//! says nothing, and `--basis` is then required.
use crate::io::image::{Image, ImageHeader};
use glyphcast::error::{Message, Piece};
use glyphcast::glyph::sh::{ShBasis, parse_basis};
use glyphcast::glyph::tensor_order::TensorOrder;
use glyphcast::glyph::{Symmetry, TensorLayout};
use glyphcast::{Error, Result, Setting};

/// What starts the SH description `fit` writes, before the band.
const FIT_SH_PREFIX: &str = "glyphcast fit: SH band ";

/// What starts the description of a tensor fit, before the order.
pub const TENSOR_PREFIX: &str = "glyphcast fit: symmetric tensor order ";

/// The description of a tensor fit written with its entries in `stored` order: "glyphcast
/// fit: symmetric tensor order 2 in mrtrix order" (`recorded_tensor_order` reads
/// it back; a description without " in NAME order", as glyphcast wrote before it
/// recorded the order, means glyphcast's order).
pub fn tensor_description(order: u32, stored: TensorOrder) -> String {
    format!("{TENSOR_PREFIX}{order} in {stored} order")
}

/// What starts the description of `glyphcast peaks`' output.
const PEAKS_PREFIX: &str = "glyphcast peaks: ";

/// What a file's glyphcast description says it holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RecordedContent {
    /// SH coefficients (`glyphcast fit --sh` or `--odf`).
    Sh,
    /// A symmetric tensor of this order per voxel (`glyphcast fit --order N`).
    Tensor(u32),
    /// Fibre peaks (`glyphcast peaks`).
    Peaks,
}

/// What `image`'s description says it holds, if glyphcast wrote it.
pub fn recorded_content(image: &Image) -> Option<RecordedContent> {
    let description = image.description()?;
    description.lines().find_map(|line| {
        if line.contains(FIT_SH_PREFIX) {
            Some(RecordedContent::Sh)
        } else if let Some(at) = line.find(TENSOR_PREFIX) {
            let order = line[at + TENSOR_PREFIX.len()..]
                .split_whitespace()
                .next()?
                .parse()
                .ok()?;
            Some(RecordedContent::Tensor(order))
        } else if line.contains(PEAKS_PREFIX) {
            Some(RecordedContent::Peaks)
        } else {
            None
        }
    })
}

/// Refuses `image`, read as `wanted`, when its description says it holds something else
/// (an SH fit read as tensors, peaks read as coefficients, ...): an error naming the file
/// and the field, and what to read it as.
pub fn check_content(image: &Image, wanted: RecordedContent) -> Result<()> {
    let Some(recorded) = recorded_content(image) else {
        return Ok(());
    };
    let same = matches!(
        (recorded, wanted),
        (RecordedContent::Sh, RecordedContent::Sh)
            | (RecordedContent::Peaks, RecordedContent::Peaks)
            | (RecordedContent::Tensor(_), RecordedContent::Tensor(_))
    );
    if same {
        return Ok(());
    }
    let holds = match recorded {
        RecordedContent::Sh => "records SH coefficients (glyphcast fit)".to_string(),
        RecordedContent::Tensor(order) => {
            format!("records a symmetric tensor of order {order} (glyphcast fit)")
        }
        RecordedContent::Peaks => "records fibre peaks (glyphcast peaks)".to_string(),
    };
    let not = match wanted {
        RecordedContent::Sh => ", not SH coefficients",
        RecordedContent::Tensor(_) => ", not tensors",
        RecordedContent::Peaks => ", not peaks",
    };
    let mut pieces: Vec<Piece> = vec![holds.into(), not.into()];
    match recorded {
        RecordedContent::Sh => pieces.push(": read it as an SH volume".into()),
        // Only render and view read tensor volumes (qc and peaks take SH alone), so the
        // way out names them rather than an option the caller may lack.
        RecordedContent::Tensor(order) => pieces.extend([
            ": render or view draw it as a tensor volume (with ".into(),
            Setting::Order.with(order),
            "); qc and peaks read SH coefficients only".into(),
        ]),
        RecordedContent::Peaks => pieces.extend([": give it as ".into(), Setting::Peaks.into()]),
    }
    Err(Error::input(
        &image.file,
        description_field(image),
        Message::from_pieces(pieces),
    ))
}

/// A basis read from a file's header.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RecordedBasis {
    /// The basis convention the writer recorded.
    pub basis: ShBasis,
    /// Whether it recorded DIPY's legacy variant of that basis.
    pub legacy: bool,
    /// The header field it was read from: `descrip` (NIfTI) or `comments` (MRtrix).
    pub field: &'static str,
}

/// The header field that holds a file's description: `descrip` or `comments`.
pub(crate) fn description_field(image: &Image) -> &'static str {
    match image.header {
        ImageHeader::Nifti(_) => "descrip",
        ImageHeader::Mrtrix(_) => "comments",
    }
}

/// The header key in which `fit` also records the basis of a `.mif` ("descoteaux07
/// legacy"), beside the description in `comments`.
const BASIS_KEY: &str = "glyphcast_sh_basis";

/// The basis `image` records: in its description (a description of another kind records
/// none), and in a `.mif` also under `glyphcast_sh_basis`. A basis name glyphcast does not know,
/// or two records that disagree, are errors naming the file and the field: such a file
/// is not read in a basis it may not be in.
pub fn recorded_basis(image: &Image) -> Result<Option<RecordedBasis>> {
    let field = description_field(image);
    let described = match image.description() {
        Some(description) => description
            .lines()
            .find_map(|line| {
                let rest = &line[line.find(FIT_SH_PREFIX)? + FIT_SH_PREFIX.len()..];
                Some(rest.split_whitespace().skip(1).collect::<Vec<_>>())
            })
            .map(|words| named_basis(image, field, &words))
            .transpose()?,
        None => None,
    };
    let keyed = match &image.header {
        ImageHeader::Mrtrix(header) => header
            .other
            .iter()
            .find(|(key, _)| key == BASIS_KEY)
            .map(|(_, value)| {
                named_basis(
                    image,
                    BASIS_KEY,
                    &value.split_whitespace().collect::<Vec<_>>(),
                )
            })
            .transpose()?,
        ImageHeader::Nifti(_) => None,
    };
    match (described, keyed) {
        (Some(a), Some(b)) if (a.basis, a.legacy) != (b.basis, b.legacy) => Err(Error::input(
            &image.file,
            BASIS_KEY,
            Message::from_pieces(
                [
                    vec!["records the SH basis ".into()],
                    show(b.basis, b.legacy),
                    vec![format!(", but {field} records ").into()],
                    show(a.basis, a.legacy),
                    vec![": the file does not say which basis it is in".into()],
                ]
                .concat(),
            ),
        )),
        (Some(recorded), _) | (None, Some(recorded)) => Ok(Some(recorded)),
        (None, None) => Ok(None),
    }
}

/// The basis of a record's words, `NAME [legacy] ...`, read from `field` of `image`.
fn named_basis(image: &Image, field: &'static str, words: &[&str]) -> Result<RecordedBasis> {
    let name = words.first().copied().unwrap_or("");
    let legacy = words.get(1) == Some(&"legacy");
    let (basis, legacy) = parse_basis(name, legacy).map_err(|_| {
        Error::input(
            &image.file,
            field,
            format!(
                "records the SH basis '{}', which is none glyphcast knows (tournier07, \
                 descoteaux07): the file is not read in a basis it may not be in",
                glyphcast::error::quoted(name)
            ),
        )
    })?;
    Ok(RecordedBasis {
        basis,
        legacy,
        field,
    })
}

/// The basis's name, with the legacy setting after it for its legacy variant
/// (`descoteaux07 --legacy` on the command line), as pieces of a message.
fn show(basis: ShBasis, legacy: bool) -> Vec<Piece> {
    let mut pieces = vec![Piece::from(basis.name())];
    if legacy {
        pieces.extend([Piece::from(" "), Piece::from(Setting::Legacy)]);
    }
    pieces
}

/// A basis named `descoteaux07` without a legacy choice (`legacy` unset), where nothing
/// else decides the variant, is refused: DIPY 1.x writes the legacy basis unless told
/// otherwise and calls the non-legacy one by the same name, so the bare name could be
/// either. A file that records its basis decides (unless `force` draws the given basis
/// anyway); a file that records none, or coefficients in memory (`image` `None`, named
/// `name`), do not. The error names the data and both choices: the aliases `dipy` and
/// `dipy-new`.
pub fn check_variant_named(
    basis: Option<&str>,
    legacy: Option<bool>,
    force: bool,
    image: Option<&Image>,
    name: &str,
) -> Result<()> {
    let Some(basis) = basis.filter(|basis| basis.trim().eq_ignore_ascii_case("descoteaux07"))
    else {
        return Ok(());
    };
    if legacy.is_some() {
        return Ok(());
    }
    let (decided, records_none) = match image {
        Some(image) => (
            !force && recorded_basis(image)?.is_some(),
            format!("{name} records no SH basis"),
        ),
        None => (
            false,
            format!("{name} is an array, which records no SH basis"),
        ),
    };
    if decided {
        return Ok(());
    }
    Err(Error::setting_value(
        Setting::Basis,
        format!("'{}'", glyphcast::error::quoted(basis)),
        glyphcast::message![
            format!(
                "names two bases and {records_none}: DIPY 1.x writes the legacy variant \
                 unless told otherwise (its default legacy=True); give "
            ),
            Setting::Basis.with("dipy"),
            " (or ",
            Setting::Legacy,
            ") for that one, or ",
            Setting::Basis.with("dipy-new"),
            " for the non-legacy one"
        ],
    ))
}

/// The basis to draw `image` in: `given` (the basis setting) when it agrees with what
/// the file records or `force` is set, else the recorded one, else tournier07 for an
/// MRtrix file. A contradiction is an error naming the file and the field; no basis at
/// all is an [`Error::Setting`] naming the basis.
pub fn resolve_basis(
    image: &Image,
    given: Option<(ShBasis, bool)>,
    force: bool,
) -> Result<(ShBasis, bool)> {
    let recorded = recorded_basis(image)?;
    match (given, recorded) {
        (Some(given), Some(recorded)) if !force && given != (recorded.basis, recorded.legacy) => {
            Err(Error::input(
                &image.file,
                recorded.field,
                Message::from_pieces(
                    [
                        vec!["the file records the SH basis ".into()],
                        show(recorded.basis, recorded.legacy),
                        vec![" but ".into(), Setting::Basis.into(), " gives ".into()],
                        show(given.0, given.1),
                        vec![
                            "; leave out ".into(),
                            Setting::Basis.into(),
                            ", or add ".into(),
                            Setting::ForceBasis.into(),
                            " to draw in ".into(),
                        ],
                        show(given.0, given.1),
                        vec![" anyway".into()],
                    ]
                    .concat(),
                ),
            ))
        }
        (Some(given), _) => Ok(given),
        (None, Some(recorded)) => Ok((recorded.basis, recorded.legacy)),
        (None, None) => match image.header {
            ImageHeader::Mrtrix(_) => Ok((ShBasis::Tournier07, false)),
            ImageHeader::Nifti(_) => Err(Error::setting(
                Setting::Basis,
                glyphcast::message![
                    "an SH volume needs its basis, one of tournier07, descoteaux07, mrtrix, \
                     dipy or dipy-new (with ",
                    Setting::Legacy,
                    format!(
                        " for a legacy variant, such as MRtrix 0.2's): {} records no SH \
                         basis in its {}",
                        image.file,
                        description_field(image)
                    )
                ],
            )),
        },
    }
}

/// The stored order `image` records in its description ([`tensor_description`]):
/// the name of " in NAME order" after the tensor fit's prefix, glyphcast's when a tensor
/// fit's description has none (glyphcast wrote that before it recorded the order), and
/// `None` where there is no tensor fit's description (or the name is unknown).
pub fn recorded_tensor_order(image: &Image) -> Option<TensorOrder> {
    let description = image.description()?;
    description.lines().find_map(|line| {
        let rest = &line[line.find(TENSOR_PREFIX)? + TENSOR_PREFIX.len()..];
        let mut words = rest.split_whitespace().skip(1);
        match (words.next(), words.next(), words.next()) {
            (None, ..) => Some(TensorOrder::Glyphcast),
            (Some("in"), Some(name), Some("order")) => name.parse().ok(),
            _ => None,
        }
    })
}

/// Where the stored order of a tensor volume's entries comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OrderSource {
    /// The tensor order setting.
    Given,
    /// The file's description (a file glyphcast wrote).
    Recorded,
    /// The convention of the file's format (MRtrix for a `.mif`) or glyphcast's where
    /// nothing says: to be checked against the values.
    Assumed,
}

/// The stored order to read a tensor volume of `layout` in: `given` (the tensor order
/// setting) unless the file records another; else the file's record; else MRtrix's for an
/// order-2 `.mif` (every MRtrix tensor) and glyphcast's otherwise (`image` is `None` for
/// coefficients in memory). An order-4 `.mif` without a record is refused: it may be
/// `dwi2tensor -dkt`'s kurtosis tensor, in an order glyphcast does not read.
pub fn resolve_tensor_order(
    image: Option<&Image>,
    given: Option<TensorOrder>,
    layout: TensorLayout,
) -> Result<(TensorOrder, OrderSource)> {
    let symmetric = layout.symmetry == Symmetry::Symmetric;
    if let Some(given) = given {
        given.check_applies(layout.order, symmetric)?;
    }
    let recorded = image.and_then(|image| Some((image, recorded_tensor_order(image)?)));
    match (given, recorded) {
        (Some(given), Some((image, recorded))) if !given.stores_like(recorded) => {
            Err(Error::input(
                &image.file,
                description_field(image),
                glyphcast::message![
                    format!(
                        "the file records its tensor entries in {}'s order ({}) but ",
                        recorded.owner(),
                        recorded.entries()
                    ),
                    Setting::TensorOrder,
                    format!(
                        " \
                     gives {given} ({}); leave it out",
                        given.entries()
                    )
                ],
            ))
        }
        (Some(given), _) => Ok((given, OrderSource::Given)),
        (None, Some((_, recorded))) => Ok((recorded, OrderSource::Recorded)),
        (None, None) => match image.map(|image| (image, &image.header)) {
            Some((image, ImageHeader::Mrtrix(_))) if symmetric && layout.order == 4 => {
                Err(Error::input(
                    &image.file,
                    "comments",
                    glyphcast::message![
                        "an order-4 MRtrix image that glyphcast did not write may be \
                         dwi2tensor -dkt's kurtosis tensor, whose order glyphcast does not \
                         read; give ",
                        Setting::TensorOrder.with("glyphcast"),
                        " if its entries are in glyphcast's order"
                    ],
                ))
            }
            Some((_, ImageHeader::Mrtrix(_))) if symmetric && layout.order == 2 => {
                Ok((TensorOrder::Mrtrix, OrderSource::Assumed))
            }
            _ => Ok((TensorOrder::Glyphcast, OrderSource::Assumed)),
        },
    }
}

/// Whether `layout` stores the six entries whose order can differ between writers.
pub fn has_dti_entries(layout: TensorLayout) -> bool {
    layout.order == 2 && layout.symmetry == Symmetry::Symmetric
}

#[cfg(test)]
/// For tests: an MRtrix image whose `comments` hold `text`, through the image writer
/// (`io::image::image_bytes`, as `fit` writes its record) and the parser.
pub(crate) fn commented_image(text: &str) -> Image {
    use crate::io::image::{ImageWrite, image_bytes};
    use crate::io::mif::MifHeader;
    use crate::io::nifti::{AffineSource, VoxelToWorld};
    use glam::DMat4;
    let data = ndarray::ArrayD::zeros(ndarray::IxDyn(&[1, 1, 1]));
    let voxel_to_world =
        VoxelToWorld::new(DMat4::IDENTITY, AffineSource::Pixdim, "f.mif", "transform").unwrap();
    let bytes = image_bytes(
        std::path::Path::new("f.mif"),
        &ImageWrite {
            data: data.view(),
            voxel_to_world: &voxel_to_world,
            nifti_reference: None,
            description: text,
            mrtrix_keys: &[],
        },
    )
    .unwrap();
    let header = MifHeader::parse(&bytes, "f.mif").unwrap();
    Image {
        file: "f.mif".into(),
        data,
        voxel_to_world,
        header: ImageHeader::Mrtrix(Box::new(header)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn given_and_recorded_must_agree_unless_forced() {
        let image = commented_image("glyphcast fit: SH band 4 descoteaux07 lambda 0");
        let dipy_new = (ShBasis::Descoteaux07, false);
        let mrtrix = (ShBasis::Tournier07, false);
        assert_eq!(resolve_basis(&image, None, false).unwrap(), dipy_new);
        assert_eq!(
            resolve_basis(&image, Some(dipy_new), false).unwrap(),
            dipy_new
        );
        let err = resolve_basis(&image, Some(mrtrix), false)
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("f.mif: comments: "), "{err}");
        assert_eq!(resolve_basis(&image, Some(mrtrix), true).unwrap(), mrtrix);
        // An MRtrix file without a record is tournier07, and any --basis goes.
        let plain = commented_image("made by dwi2fod");
        assert_eq!(resolve_basis(&plain, None, false).unwrap(), mrtrix);
        assert_eq!(
            resolve_basis(&plain, Some(dipy_new), false).unwrap(),
            dipy_new
        );
    }

    #[test]
    fn a_bare_descoteaux07_needs_a_record_or_a_legacy_choice() {
        let recorded = commented_image("glyphcast fit: SH band 4 descoteaux07 lambda 0");
        let plain = commented_image("made by dwi2fod");
        let check = |name: &str, legacy, force, image| {
            check_variant_named(Some(name), legacy, force, image, "f.mif")
        };
        // A record decides, unless the basis is forced.
        assert!(check("descoteaux07", None, false, Some(&recorded)).is_ok());
        for (image, force, why) in [
            (Some(&plain), false, "f.mif records no SH basis"),
            (Some(&recorded), true, "f.mif records no SH basis"),
            (None, false, "f.mif is an array"),
        ] {
            let err = check(" Descoteaux07", None, force, image)
                .unwrap_err()
                .to_string();
            for words in [why, "basis dipy", "legacy", "basis dipy-new"] {
                assert!(err.contains(words), "{words}: {err}");
            }
        }
        // A legacy choice, an alias or another basis is no question.
        for legacy in [Some(true), Some(false)] {
            assert!(check("descoteaux07", legacy, false, Some(&plain)).is_ok());
        }
        for name in ["dipy", "dipy-new", "tournier07", "mrtrix"] {
            assert!(check(name, None, false, None).is_ok(), "{name}");
        }
    }
}
