use super::field::Field;
use super::json::Json;
use super::*;
use crate::camera::{Camera, Projection};
use crate::glyph::{GlyphShape, NegativeMode, Symmetry, TensorLayout};
use glam::DVec3;
use serde_json::{Value, json};

const FILE: &str = "case.json";

/// A valid scene that each test breaks in one place.
fn valid() -> Value {
    json!({
        "version": 1,
        "glyphs": [{
            "kind": "tensor",
            "order": 4,
            "centers": [[0, 0, 0], [1, 0, 0]],
            "scale": 0.45,
            "coeffs": [vec![0.5; 15], vec![-0.25; 15]]
        }],
        "camera": { "eye": [0, -6, 2], "target": [0, 0, 0] }
    })
}

fn edited(edit: impl FnOnce(&mut Value)) -> Value {
    let mut doc = valid();
    edit(&mut doc);
    doc
}

fn glyph_set(doc: &mut Value) -> &mut serde_json::Map<String, Value> {
    doc["glyphs"][0].as_object_mut().unwrap()
}

fn camera(doc: &mut Value) -> &mut serde_json::Map<String, Value> {
    doc["camera"].as_object_mut().unwrap()
}

fn parse(doc: &Value) -> Result<Scene> {
    Scene::from_json_str(&doc.to_string(), FILE)
}

/// The result is an input error at exactly `field` whose message contains
/// `fragment`, and its Display names the file and the field.
fn assert_input_error(result: Result<Scene>, field: &str, fragment: &str) {
    let err = match result {
        Err(err @ Error::Input { .. }) => err,
        other => panic!("expected an input error at {field}, got {other:?}"),
    };
    let text = err.to_string();
    let Error::Input {
        file,
        field: found,
        message,
    } = &err
    else {
        unreachable!()
    };
    assert_eq!(file, FILE, "{text}");
    assert_eq!(found, field, "{text}");
    assert!(
        message.to_string().contains(fragment),
        "{text:?} lacks {fragment:?}"
    );
    assert!(text.starts_with(&format!("{FILE}: {field}: ")), "{text}");
    assert!(!text.contains('\n'), "one line: {text}");
}

fn assert_text_error(text: &str, field_prefix: &str, fragment: &str) {
    let err = Scene::from_json_str(text, FILE).unwrap_err();
    let display = err.to_string();
    let Error::Input { file, field, .. } = &err else {
        panic!("expected an input error, got {display}");
    };
    assert_eq!(file, FILE);
    assert!(field.starts_with(field_prefix), "{display}");
    assert!(display.contains(fragment), "{display:?} lacks {fragment:?}");
}

#[test]
fn defaults_fill_in_optional_fields() {
    let scene = parse(&valid()).unwrap();
    assert_eq!(
        scene.image,
        ImageSize {
            width: 512,
            height: 512
        }
    );
    assert_eq!(scene.camera.up, DVec3::Z);
    assert_eq!(
        scene.camera.projection,
        Projection::Perspective { fov_y_deg: 30.0 }
    );
    let [set] = scene.glyph_sets.as_slice() else {
        panic!("one set")
    };
    let layout = TensorLayout {
        order: 4,
        symmetry: Symmetry::Symmetric,
    };
    assert_eq!(set.kind, GlyphKind::Tensor(layout));
    assert_eq!(set.negative, NegativeMode::Abs);
    assert_eq!(set.scales, vec![0.45, 0.45]);
    assert_eq!((set.len(), set.is_empty()), (2, false));
    assert_eq!(set.centers[1], DVec3::X);

    let sh = parse(&edited(|doc| {
        glyph_set(doc).insert("kind".into(), json!("sh"));
    }))
    .unwrap();
    let sh_kind = GlyphKind::Sh {
        band: 4,
        basis: ShBasis::Tournier07,
        legacy: false,
    };
    assert_eq!(sh.glyph_sets[0].kind, sh_kind);
    assert_eq!(sh_kind.coefficient_count(), 15);
}

#[test]
fn empty_glyph_list_and_empty_set_are_allowed() {
    let no_sets = parse(&edited(|doc| doc["glyphs"] = json!([]))).unwrap();
    assert!(no_sets.glyph_sets.is_empty());
    let empty_set = parse(&edited(|doc| {
        glyph_set(doc).insert("centers".into(), json!([]));
        glyph_set(doc).insert("coeffs".into(), json!([]));
    }))
    .unwrap();
    assert!(empty_set.glyph_sets[0].is_empty());
}

#[test]
fn malformed_json_names_line_and_column() {
    let text = "{\n  \"version\": 1,,\n  \"glyphs\": []\n}";
    assert_text_error(text, "line 2, column ", "malformed JSON");
    assert_text_error("", "line 1, column 0", "EOF while parsing");
    assert_text_error(
        "{\"version\": 1} x",
        "line 1, column",
        "trailing characters",
    );
}

#[test]
fn nan_infinity_and_huge_numbers_are_rejected() {
    let text = valid().to_string().replace("0.45", "NaN");
    assert_text_error(&text, "line 1, column", "NaN is not a valid JSON number");
    let text = valid().to_string().replace("0.45", "-Infinity");
    assert_text_error(
        &text,
        "line 1, column",
        "Infinity is not a valid JSON number",
    );
    let text = valid().to_string().replace("0.45", "1e400");
    assert_text_error(&text, "line 1, column", "number out of range");
}

#[test]
fn duplicate_keys_are_rejected() {
    let text = valid()
        .to_string()
        .replace("\"scale\":0.45", "\"scale\":0.45,\"scale\":2");
    assert_text_error(&text, "line 1, column", "duplicate key \"scale\"");
}

#[test]
fn missing_required_fields_are_named() {
    for key in ["version", "glyphs", "camera"] {
        let doc = edited(|doc| {
            doc.as_object_mut().unwrap().remove(key);
        });
        assert_input_error(parse(&doc), key, "missing required field");
    }
    for key in ["kind", "order", "centers", "coeffs"] {
        let doc = edited(|doc| {
            glyph_set(doc).remove(key);
        });
        assert_input_error(parse(&doc), &format!("glyphs[0].{key}"), "missing required");
    }
    let doc = edited(|doc| {
        glyph_set(doc).remove("scale");
    });
    assert_input_error(parse(&doc), "glyphs[0].scale", "`scales`");
    for key in ["eye", "target"] {
        let doc = edited(|doc| {
            camera(doc).remove(key);
        });
        assert_input_error(parse(&doc), &format!("camera.{key}"), "missing required");
    }
    let doc = edited(|doc| doc["image"] = json!({ "width": 64 }));
    assert_input_error(parse(&doc), "image.height", "missing required");
}

#[test]
fn only_version_1_is_read() {
    assert_input_error(
        parse(&edited(|doc| doc["version"] = json!(2))),
        "version",
        "2",
    );
    assert_input_error(
        parse(&edited(|doc| doc["version"] = json!("1"))),
        "version",
        "expected an integer",
    );
    let root = Scene::from_json_str("[1, 2]", FILE);
    assert_input_error(root, "(top level)", "expected an object");
}

#[test]
fn the_ellipsoid_shape_is_for_order_2_symmetric_tensors_without_hiding() {
    let order_2 = |doc: &mut Value| {
        glyph_set(doc).insert("order".into(), json!(2));
        glyph_set(doc).insert("coeffs".into(), json!([vec![1.0; 6], vec![2.0; 6]]));
        glyph_set(doc).insert("shape".into(), json!("ellipsoid"));
    };
    let scene = parse(&edited(order_2)).expect("order-2 ellipsoids");
    assert_eq!(scene.glyph_sets[0].shape, GlyphShape::Ellipsoid);
    assert_eq!(
        parse(&valid()).unwrap().glyph_sets[0].shape,
        GlyphShape::Polynomial
    );
    let on_order_4 = edited(|doc| {
        glyph_set(doc).insert("shape".into(), json!("ellipsoid"));
    });
    assert_input_error(parse(&on_order_4), "glyphs[0].shape", "order 2, not to a");
    let hidden = edited(|doc| {
        order_2(doc);
        glyph_set(doc).insert("negative".into(), json!("hide"));
    });
    assert_input_error(parse(&hidden), "glyphs[0].shape", "no negative lobes");
    let unknown = edited(|doc| {
        glyph_set(doc).insert("shape".into(), json!("peanut"));
    });
    assert_input_error(
        parse(&unknown),
        "glyphs[0].shape",
        "\"polynomial\", \"ellipsoid\", \"reciprocal\", \"plane-min\", \"plane-max\", \"ratio-min\", \"ratio-max\"",
    );
}

#[test]
fn the_reciprocal_shape_reads_for_any_kind_without_hiding() {
    let reciprocal = edited(|doc| {
        glyph_set(doc).insert("shape".into(), json!("reciprocal"));
    });
    let scene = parse(&reciprocal).expect("a reciprocal order-4 set");
    assert_eq!(scene.glyph_sets[0].shape, GlyphShape::Reciprocal);
    let hidden = edited(|doc| {
        glyph_set(doc).insert("shape".into(), json!("reciprocal"));
        glyph_set(doc).insert("negative".into(), json!("hide"));
    });
    assert_input_error(
        parse(&hidden),
        "glyphs[0].shape",
        "no negative lobes to hide",
    );
}

/// A plane set is symmetric order 6 with 28 + 15 coefficients a glyph (D then T), a
/// ratio set with 28 + 15 + 15 (D, T, then Q), without hiding; other orders, hidden lobes and the order-6 count alone are refused
/// naming the field.
#[test]
fn the_plane_shapes_read_d_then_t() {
    let plane = |shape: &str, count: usize, order: u32| {
        let shape = shape.to_owned();
        edited(move |doc| {
            let set = glyph_set(doc);
            set.insert("shape".into(), json!(shape));
            set.insert("order".into(), json!(order));
            set.insert("coeffs".into(), json!([vec![0.5; count], vec![0.5; count]]));
        })
    };
    for (name, shape, count) in [
        ("plane-min", GlyphShape::PlaneMin, 43),
        ("plane-max", GlyphShape::PlaneMax, 43),
        ("ratio-min", GlyphShape::RatioMin, 58),
        ("ratio-max", GlyphShape::RatioMax, 58),
    ] {
        let scene = parse(&plane(name, count, 6)).expect("a plane or ratio set");
        assert_eq!(scene.glyph_sets[0].shape, shape);
        assert_eq!(scene.glyph_sets[0].coeffs[0].len(), count);
        let written = Scene::from_json_str(&scene.to_json(), FILE).expect("written");
        assert_eq!(written, scene);
    }
    assert_input_error(
        parse(&plane("plane-min", 28, 6)),
        "glyphs[0].coeffs[0]",
        "then T",
    );
    assert_input_error(
        parse(&plane("plane-max", 15, 4)),
        "glyphs[0].shape",
        "order 6",
    );
    assert_input_error(
        parse(&plane("ratio-min", 43, 6)),
        "glyphs[0].coeffs[0]",
        "then T and Q",
    );
    assert_input_error(
        parse(&plane("ratio-max", 58, 4)),
        "glyphs[0].shape",
        "order 6",
    );
    let hidden = edited(|doc| {
        let set = glyph_set(doc);
        set.insert("shape".into(), json!("plane-min"));
        set.insert("order".into(), json!(6));
        set.insert("negative".into(), json!("hide"));
    });
    assert_input_error(parse(&hidden), "glyphs[0].shape", "no negative lobes");
}

#[test]
fn unknown_values_list_the_allowed_ones() {
    let cases = [
        ("kind", json!("tensr"), "\"tensor\", \"sh\""),
        ("negative", json!("clip"), "\"abs\", \"hide\""),
        ("negative", json!(1), "\"abs\", \"hide\""),
    ];
    for (key, value, allowed) in cases {
        let doc = edited(|doc| {
            glyph_set(doc).insert(key.into(), value);
        });
        assert_input_error(parse(&doc), &format!("glyphs[0].{key}"), allowed);
    }
    let doc = edited(|doc| {
        glyph_set(doc).insert("kind".into(), json!("sh"));
        glyph_set(doc).insert("basis".into(), json!("mrtrix"));
    });
    assert_input_error(
        parse(&doc),
        "glyphs[0].basis",
        "\"tournier07\", \"descoteaux07\"",
    );
    let doc = edited(|doc| {
        camera(doc).insert("projection".into(), json!("fisheye"));
    });
    assert_input_error(
        parse(&doc),
        "camera.projection",
        "\"perspective\", \"orthographic\"",
    );
}

#[test]
fn unknown_keys_are_named() {
    let doc = edited(|doc| {
        let centers = glyph_set(doc).remove("centers").unwrap();
        glyph_set(doc).insert("centres".into(), centers);
    });
    assert_input_error(parse(&doc), "glyphs[0].centres", "unknown key \"centres\"");
    let doc = edited(|doc| doc["imgae"] = json!({}));
    assert_input_error(parse(&doc), "imgae", "unknown key");
    let doc = edited(|doc| {
        camera(doc).insert("fov".into(), json!(40));
    });
    assert_input_error(parse(&doc), "camera.fov", "fov_y_deg");
    let doc = edited(|doc| doc["image"] = json!({ "width": 8, "height": 8, "depth": 8 }));
    assert_input_error(parse(&doc), "image.depth", "unknown key");
}

#[test]
fn options_that_do_not_apply_are_rejected() {
    let doc = edited(|doc| {
        glyph_set(doc).insert("kind".into(), json!("sh"));
        glyph_set(doc).insert("symmetric".into(), json!(true));
    });
    assert_input_error(
        parse(&doc),
        "glyphs[0].symmetric",
        "only to kind \"tensor\"",
    );
    for key in ["basis", "legacy"] {
        let value = if key == "basis" {
            json!("tournier07")
        } else {
            json!(false)
        };
        let doc = edited(|doc| {
            glyph_set(doc).insert(key.into(), value);
        });
        assert_input_error(
            parse(&doc),
            &format!("glyphs[0].{key}"),
            "only to kind \"sh\"",
        );
    }
    let doc = edited(|doc| {
        camera(doc).insert("height".into(), json!(2));
    });
    assert_input_error(parse(&doc), "camera.height", "only to orthographic");
    let doc = edited(|doc| {
        camera(doc).insert("projection".into(), json!("orthographic"));
        camera(doc).insert("height".into(), json!(2));
        camera(doc).insert("fov_y_deg".into(), json!(30));
    });
    assert_input_error(parse(&doc), "camera.fov_y_deg", "only to perspective");
}

fn with_kind(kind: &str, order: Value, symmetric: Option<bool>) -> Value {
    edited(|doc| {
        glyph_set(doc).insert("kind".into(), json!(kind));
        glyph_set(doc).insert("order".into(), order);
        if let Some(symmetric) = symmetric {
            glyph_set(doc).insert("symmetric".into(), json!(symmetric));
        }
    })
}

#[test]
fn orders_out_of_range_are_rejected() {
    let cases = [
        (
            "tensor",
            json!(0),
            None,
            "symmetric tensor order must be from 1 to 12",
        ),
        ("tensor", json!(13), Some(true), "found 13"),
        ("tensor", json!(5), Some(false), "supported up to order 4"),
        ("tensor", json!(0), Some(false), "supported up to order 4"),
        ("tensor", json!(-1), None, "found -1"),
        ("sh", json!(3), None, "even"),
        ("sh", json!(14), None, "from 0 to 12"),
        ("sh", json!(-2), None, "found -2"),
        ("tensor", json!(4.0), None, "expected an integer"),
        ("tensor", json!(1e30), None, "expected an integer"),
    ];
    for (kind, order, symmetric, fragment) in cases {
        let doc = with_kind(kind, order, symmetric);
        assert_input_error(parse(&doc), "glyphs[0].order", fragment);
    }
}

#[test]
fn coefficient_counts_follow_the_kind() {
    let doc = edited(|doc| doc["glyphs"][0]["coeffs"][1] = json!(vec![1.0; 14]));
    assert_input_error(
        parse(&doc),
        "glyphs[0].coeffs[1]",
        "expected 15 coefficients (symmetric tensor of order 4), found 14",
    );
    let doc = with_kind("tensor", json!(4), Some(false));
    assert_input_error(
        parse(&doc),
        "glyphs[0].coeffs[0]",
        "expected 81 coefficients (non-symmetric tensor of order 4), found 15",
    );
    let doc = with_kind("sh", json!(6), None);
    assert_input_error(
        parse(&doc),
        "glyphs[0].coeffs[0]",
        "expected 28 coefficients (SH",
    );
    let nonsymmetric = edited(|doc| {
        glyph_set(doc).insert("order".into(), json!(2));
        glyph_set(doc).insert("symmetric".into(), json!(false));
        glyph_set(doc).insert("coeffs".into(), json!([vec![1.0; 9], vec![0.0; 9]]));
    });
    assert_eq!(
        parse(&nonsymmetric).unwrap().glyph_sets[0].coeffs[0].len(),
        9
    );
}

#[test]
fn per_glyph_lists_match_the_centers() {
    let doc = edited(|doc| doc["glyphs"][0]["coeffs"] = json!([vec![0.0; 15]]));
    assert_input_error(
        parse(&doc),
        "glyphs[0].coeffs",
        "expected 2 coefficient lists",
    );
    let doc = edited(|doc| {
        glyph_set(doc).remove("scale");
        glyph_set(doc).insert("scales".into(), json!([1.0]));
    });
    assert_input_error(parse(&doc), "glyphs[0].scales", "expected 2 scales");
    let doc = edited(|doc| {
        glyph_set(doc).insert("scales".into(), json!([1.0, 2.0]));
    });
    assert_input_error(parse(&doc), "glyphs[0].scales", "not both");
    let doc = edited(|doc| doc["glyphs"][0]["centers"][1] = json!([1, 0]));
    assert_input_error(parse(&doc), "glyphs[0].centers[1]", "3 numbers");
    let doc = edited(|doc| doc["glyphs"][0]["centers"] = json!({}));
    assert_input_error(parse(&doc), "glyphs[0].centers", "expected a list");
}

#[test]
fn numbers_must_be_finite_numbers_and_scales_positive() {
    let doc = edited(|doc| doc["glyphs"][0]["coeffs"][1][3] = json!("x"));
    assert_input_error(parse(&doc), "glyphs[0].coeffs[1][3]", "expected a number");
    let doc = edited(|doc| doc["glyphs"][0]["centers"][0][2] = json!(null));
    assert_input_error(parse(&doc), "glyphs[0].centers[0][2]", "found null");
    let doc = edited(|doc| doc["glyphs"][0]["scale"] = json!(0));
    assert_input_error(parse(&doc), "glyphs[0].scale", "must be positive");
    let doc = edited(|doc| {
        glyph_set(doc).remove("scale");
        glyph_set(doc).insert("scales".into(), json!([1.0, -2.0]));
    });
    assert_input_error(parse(&doc), "glyphs[0].scales[1]", "found -2");
    let doc = edited(|doc| doc["camera"]["eye"][1] = json!(true));
    assert_input_error(parse(&doc), "camera.eye[1]", "expected a number");
    // serde_json never produces a non-finite number; the tree check still guards.
    let inf = Json::Float(f64::INFINITY);
    let err = Field::root(FILE, &inf).number().unwrap_err();
    assert!(err.to_string().contains("finite"), "{err}");
}

/// The GPU draws in float32: a finite float64 beyond its range would be infinite there
/// and the glyph (or the whole view) would vanish, so the reader refuses it by field.
#[test]
fn numbers_beyond_float32_are_refused() {
    let beyond = "1e39 is beyond float32's range";
    let doc = edited(|doc| doc["glyphs"][0]["coeffs"][1][3] = json!(1e39));
    assert_input_error(parse(&doc), "glyphs[0].coeffs[1][3]", beyond);
    let doc = edited(|doc| doc["glyphs"][0]["coeffs"][0][0] = json!(-1e39));
    assert_input_error(parse(&doc), "glyphs[0].coeffs[0][0]", "-1e39 is beyond");
    let doc = edited(|doc| doc["glyphs"][0]["centers"][1][0] = json!(1e39));
    assert_input_error(parse(&doc), "glyphs[0].centers[1][0]", beyond);
    let doc = edited(|doc| doc["glyphs"][0]["scale"] = json!(1e39));
    assert_input_error(parse(&doc), "glyphs[0].scale", beyond);
    let doc = edited(|doc| doc["camera"]["eye"][0] = json!(1e39));
    assert_input_error(parse(&doc), "camera.eye[0]", beyond);
    let doc = edited(|doc| doc["camera"]["target"][2] = json!(1e300));
    assert_input_error(parse(&doc), "camera.target[2]", "1e300 is beyond");
    // float32's largest value itself is taken.
    let largest = f64::from(f32::MAX);
    let doc = edited(|doc| doc["glyphs"][0]["coeffs"][1][3] = json!(largest));
    assert_eq!(parse(&doc).unwrap().glyph_sets[0].coeffs[1][3], largest);
}

#[test]
fn camera_must_define_a_view() {
    let doc = edited(|doc| doc["camera"]["target"] = json!([0, -6, 2]));
    assert_input_error(parse(&doc), "camera.target", "must differ from eye");
    let doc = edited(|doc| {
        camera(doc).insert("up".into(), json!([0, 3, -1]));
    });
    assert_input_error(parse(&doc), "camera.up", "parallel");
    let doc = edited(|doc| doc["camera"]["eye"] = json!([0, 0, 5]));
    assert_input_error(parse(&doc), "camera.up", "the default");
    let doc = edited(|doc| {
        camera(doc).insert("up".into(), json!([0, 0, 0]));
    });
    assert_input_error(parse(&doc), "camera.up", "nonzero");
    for fov in [0.0, 180.0, -10.0] {
        let doc = edited(|doc| {
            camera(doc).insert("fov_y_deg".into(), json!(fov));
        });
        assert_input_error(parse(&doc), "camera.fov_y_deg", "between 0 and 180");
    }
    let doc = edited(|doc| {
        camera(doc).insert("projection".into(), json!("orthographic"));
    });
    assert_input_error(parse(&doc), "camera.height", "missing required");
    let doc = edited(|doc| {
        camera(doc).insert("projection".into(), json!("orthographic"));
        camera(doc).insert("height".into(), json!(-1));
    });
    assert_input_error(parse(&doc), "camera.height", "must be positive");
}

#[test]
fn image_sides_are_bounded_integers() {
    for (width, fragment) in [
        (json!(0), "from 1 to 16384"),
        (json!(16385), "found 16385"),
        (json!(64.5), "expected an integer"),
    ] {
        let doc = edited(|doc| doc["image"] = json!({ "width": width, "height": 8 }));
        assert_input_error(parse(&doc), "image.width", fragment);
    }
    let doc = edited(|doc| doc["image"] = json!({ "width": 16384, "height": 1 }));
    let image = parse(&doc).unwrap().image;
    assert_eq!(
        image,
        ImageSize {
            width: 16384,
            height: 1
        }
    );
}

fn mixed_scene() -> Scene {
    let symmetric = GlyphSet {
        kind: GlyphKind::Tensor(TensorLayout {
            order: 2,
            symmetry: Symmetry::Symmetric,
        }),
        negative: NegativeMode::Hide,
        shape: GlyphShape::Polynomial,
        centers: vec![DVec3::new(0.5, -1.25, 3.0), DVec3::new(1e-3, 2e5, -7.75)],
        scales: vec![0.3, 0.3],
        coeffs: vec![vec![1.0, 0.1, -0.2, 2.0, 0.0, 0.5], vec![0.0; 6]],
    };
    let stiffness = GlyphSet {
        kind: GlyphKind::Tensor(TensorLayout {
            order: 4,
            symmetry: Symmetry::NonSymmetric,
        }),
        negative: NegativeMode::Abs,
        shape: GlyphShape::Polynomial,
        centers: vec![DVec3::ZERO],
        scales: vec![1.5],
        coeffs: vec![(0..81).map(|i| f64::from(i) * 0.125 - 3.0).collect()],
    };
    let sh = GlyphSet {
        kind: GlyphKind::Sh {
            band: 2,
            basis: ShBasis::Descoteaux07,
            legacy: true,
        },
        negative: NegativeMode::Abs,
        shape: GlyphShape::Polynomial,
        centers: vec![DVec3::X, DVec3::Y, DVec3::Z],
        scales: vec![0.25, 0.5, 0.75],
        coeffs: vec![vec![0.28, 0.01, -0.02, 0.03, 0.04, 0.05]; 3],
    };
    let empty = GlyphSet {
        centers: vec![],
        scales: vec![],
        coeffs: vec![],
        ..sh.clone()
    };
    let ellipsoids = GlyphSet {
        negative: NegativeMode::Abs,
        shape: GlyphShape::Ellipsoid,
        ..symmetric.clone()
    };
    let reciprocal = GlyphSet {
        negative: NegativeMode::Abs,
        shape: GlyphShape::Reciprocal,
        ..symmetric.clone()
    };
    Scene {
        glyph_sets: vec![symmetric, stiffness, sh, empty, ellipsoids, reciprocal],
        camera: Camera {
            projection: Projection::Orthographic { height: 4.5 },
            eye: DVec3::new(0.0, -6.0, 2.0),
            target: DVec3::new(0.0, 0.0, 0.1),
            up: DVec3::new(0.0, 0.2, 1.0),
        },
        image: ImageSize {
            width: 800,
            height: 600,
        },
    }
}

#[test]
fn to_json_round_trips() {
    let scene = mixed_scene();
    let text = scene.to_json();
    let back = Scene::from_json_str(&text, FILE).unwrap();
    assert_eq!(back, scene);
    assert_eq!(back.to_json(), text);
    let doc: Value = serde_json::from_str(&text).unwrap();
    assert_eq!(doc["glyphs"][0]["scale"], json!(0.3));
    assert!(doc["glyphs"][0].get("scales").is_none());
    assert_eq!(doc["glyphs"][2]["scales"], json!([0.25, 0.5, 0.75]));
    assert_eq!(doc["glyphs"][3]["scales"], json!([]));
    assert_eq!(doc["glyphs"][2]["basis"], json!("descoteaux07"));
    assert_eq!(doc["camera"]["height"], json!(4.5));

    let mut perspective = scene;
    perspective.camera.projection = Projection::Perspective { fov_y_deg: 42.5 };
    let back = Scene::from_json_str(&perspective.to_json(), FILE).unwrap();
    assert_eq!(back, perspective);
}

#[test]
fn to_json_puts_each_glyph_on_one_line() {
    let text = mixed_scene().to_json();
    assert!(
        text.contains("\n        [1.0, 0.1, -0.2, 2.0, 0.0, 0.5],\n"),
        "{text}"
    );
    assert!(text.contains("\"eye\": [0.0, -6.0, 2.0],"), "{text}");
    assert!(
        text.starts_with("{\n  \"version\": 1,\n  \"glyphs\": [\n"),
        "{text}"
    );
    assert!(text.ends_with("}\n"));
}

fn fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/scenes")
        .join(name)
}

#[test]
fn fixture_scenes_load() {
    let sphere = Scene::load(&fixture("sphere.json")).unwrap();
    let layout = TensorLayout {
        order: 2,
        symmetry: Symmetry::Symmetric,
    };
    assert_eq!(sphere.glyph_sets[0].kind, GlyphKind::Tensor(layout));
    assert_eq!(
        sphere.glyph_sets[0].coeffs,
        vec![vec![1.0, 0.0, 0.0, 1.0, 0.0, 1.0]]
    );
    let pair = Scene::load(&fixture("order4_pair.json")).unwrap();
    assert_eq!(pair.glyph_sets[0].len(), 2);

    let stiffness = Scene::load(&fixture("stiffness_nonsym4.json")).unwrap();
    let c = &stiffness.glyph_sets[0].coeffs[0];
    let entry = |i: usize, j: usize, k: usize, l: usize| c[27 * i + 9 * j + 3 * k + l];
    let (c11, c12, c44) = (1.0, 121.4 / 168.4, 75.4 / 168.4);
    let close = |a: f64, b: f64| (a - b).abs() < 1e-15;
    assert!(close(entry(2, 2, 2, 2), c11) && close(entry(0, 0, 1, 1), c12));
    assert!(close(entry(1, 2, 2, 1), c44) && close(entry(0, 2, 0, 2), c44));
    assert_eq!(entry(0, 0, 0, 1), 0.0);
    // Major and minor symmetries of a stiffness tensor.
    for (i, j, k, l) in (0..81).map(|n| (n / 27, n / 9 % 3, n / 3 % 3, n % 3)) {
        assert_eq!(entry(i, j, k, l), entry(j, i, k, l));
        assert_eq!(entry(i, j, k, l), entry(k, l, i, j));
    }
}

#[test]
fn bad_fixtures_fail_with_their_field() {
    let expectations = [
        ("bad_version.json", "version", "unsupported version 2"),
        ("camera_up_parallel.json", "camera.up", "parallel"),
        (
            "count_mismatch.json",
            "glyphs[0].coeffs",
            "expected 2 coefficient lists",
        ),
        (
            "duplicate_key.json",
            "line 13, column",
            "duplicate key \"scale\"",
        ),
        ("huge_number.json", "line 14, column", "number out of range"),
        ("image_too_large.json", "image.width", "found 20000"),
        ("malformed.json", "line 7, column", "malformed JSON"),
        ("missing_field.json", "version", "missing required field"),
        (
            "nan.json",
            "line 14, column",
            "NaN is not a valid JSON number",
        ),
        (
            "nonpositive_scale.json",
            "glyphs[0].scale",
            "must be positive",
        ),
        (
            "order_out_of_range.json",
            "glyphs[0].order",
            "supported up to order 4",
        ),
        (
            "orthographic_without_height.json",
            "camera.height",
            "missing required",
        ),
        (
            "symmetric_on_sh.json",
            "glyphs[0].symmetric",
            "only to kind \"tensor\"",
        ),
        (
            "unknown_key.json",
            "glyphs[0].centres",
            "unknown key \"centres\"",
        ),
        ("unknown_value.json", "glyphs[0].kind", "\"tensor\", \"sh\""),
        (
            "wrong_coeff_count.json",
            "glyphs[0].coeffs[0]",
            "expected 6 coefficients",
        ),
        (
            "wrong_type.json",
            "glyphs[0].centers[0][2]",
            "expected a number",
        ),
    ];
    for (name, field_prefix, fragment) in expectations {
        let path = fixture(&format!("bad/{name}"));
        let err = Scene::load(&path).unwrap_err();
        let text = err.to_string();
        let Error::Input { file, field, .. } = &err else {
            panic!("{name}: {text}")
        };
        assert_eq!(file, &path.display().to_string());
        assert!(field.starts_with(field_prefix), "{name}: {text}");
        assert!(text.contains(fragment), "{name}: {text}");
    }
    let mut on_disk: Vec<String> = std::fs::read_dir(fixture("bad"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    on_disk.sort();
    let listed: Vec<&str> = expectations.iter().map(|(name, ..)| *name).collect();
    assert_eq!(on_disk, listed, "every bad fixture needs an expectation");
}

#[test]
fn unreadable_file_is_an_io_error() {
    let err = Scene::load(&fixture("no_such_scene.json")).unwrap_err();
    assert!(matches!(err, Error::Io { .. }), "{err}");
    assert!(err.to_string().contains("no_such_scene.json"), "{err}");
}
