//! Holds the Rust side of the shader interface to the compiled SPIR-V: the frame block
//! `FrameParams` (member count and byte offsets against the `#[repr(C)]` struct), the
//! descriptor bindings each pass creates, and the push-constant blocks. The GLSL is
//! written by hand beside the Rust structs; these tests read the blocks back out of every
//! shader build.rs compiled, so a change on one side alone fails here. (The `exact`
//! fragment shaders go through spirv-opt, which strips every name from the SPIR-V, while
//! the other shaders keep theirs: blocks are known by storage class and binding, which
//! every shader keeps.)
use std::collections::HashMap;
use std::mem::offset_of;

use crate::render::compute::ComputeParams;
use crate::render::frame::FrameParams;
use crate::render::raycast::{
    COEFFICIENTS_BINDING, FRAME_BINDING, PIECES_BINDING, SHADOW_BINDINGS,
};
use crate::render::shaders::{
    COMPOSE_COLOR_ONLY_FRAGMENT, COMPOSE_FRAGMENT, COMPOSE_VERTEX, COMPUTE_RAYCAST_SHADERS,
    IMPOSTOR_FRAGMENT, MESH_FRAGMENT, MESH_VERTEX, RAYCAST_SHADERS, RAYCAST_VERTEX, RaycastShader,
    UNDERLAY_FRAGMENT, UNDERLAY_VERTEX,
};
use crate::render::shadow_grid::GridHeader;
use crate::render::underlay::{PARAMS_BINDING, PlanePush, UnderlayParams, VALUES_BINDING};
use crate::render::{Method, ShapeShader};

/// A block (uniform, storage or push-constant) as the SPIR-V declares it.
#[derive(Debug, Default)]
struct Block {
    storage_class: u32,
    set: Option<u32>,
    binding: Option<u32>,
    /// Member byte offsets, in declaration order.
    offsets: Vec<u32>,
}

const OP_TYPE_STRUCT: u32 = 30;
const OP_TYPE_POINTER: u32 = 32;
const OP_VARIABLE: u32 = 59;
const OP_DECORATE: u32 = 71;
const OP_MEMBER_DECORATE: u32 = 72;
const DECORATION_BINDING: u32 = 33;
const DECORATION_SET: u32 = 34;
const DECORATION_OFFSET: u32 = 35;
const UNIFORM: u32 = 2;
const PUSH_CONSTANT: u32 = 9;
const STORAGE_BUFFER: u32 = 12;

/// Every uniform, storage or push-constant variable of `spirv` whose type is a pointer to
/// a struct: its block.
fn blocks(spirv: &[u32]) -> Vec<Block> {
    assert_eq!(spirv.first(), Some(&0x0723_0203), "SPIR-V magic");
    let mut offsets: HashMap<(u32, u32), u32> = HashMap::new();
    let mut member_counts = HashMap::new();
    let mut pointers = HashMap::new();
    let mut decorations: HashMap<(u32, u32), u32> = HashMap::new();
    let mut variables = Vec::new();
    let mut at = 5;
    while at < spirv.len() {
        let (count, op) = ((spirv[at] >> 16) as usize, spirv[at] & 0xffff);
        assert!(count > 0 && at + count <= spirv.len(), "malformed SPIR-V");
        let args = &spirv[at + 1..at + count];
        match op {
            OP_TYPE_STRUCT => {
                member_counts.insert(args[0], args.len() as u32 - 1);
            }
            OP_TYPE_POINTER => {
                pointers.insert(args[0], args[2]);
            }
            OP_VARIABLE => variables.push((args[0], args[1], args[2])),
            OP_DECORATE if args.len() >= 3 => {
                decorations.insert((args[0], args[1]), args[2]);
            }
            OP_MEMBER_DECORATE if args[2] == DECORATION_OFFSET => {
                offsets.insert((args[0], args[1]), args[3]);
            }
            _ => {}
        }
        at += count;
    }
    variables
        .into_iter()
        .filter(|&(_, _, class)| [UNIFORM, STORAGE_BUFFER, PUSH_CONSTANT].contains(&class))
        .filter_map(|(pointer, variable, storage_class)| {
            let structure = *pointers.get(&pointer)?;
            let count = *member_counts.get(&structure)?;
            let offsets = (0..count)
                .map(|m| offsets.get(&(structure, m)).copied().unwrap_or(u32::MAX))
                .collect();
            Some(Block {
                storage_class,
                set: decorations.get(&(variable, DECORATION_SET)).copied(),
                binding: decorations.get(&(variable, DECORATION_BINDING)).copied(),
                offsets,
            })
        })
        .collect()
}

/// Byte offsets of a `#[repr(C)]` struct's fields, in order.
macro_rules! offsets {
    ($ty:ty: $($field:ident),*) => {
        vec![$(offset_of!($ty, $field) as u32),*]
    };
}

/// `FrameParams`'s field offsets on the Rust side.
fn frame_params_rust() -> Vec<u32> {
    offsets!(FrameParams:
        view_proj,
        eye,
        right,
        up,
        fwd,
        viewport,
        march,
        modes,
        magnitude_range,
        uniform_color,
        light,
        robust,
        negative_color,
        shading,
        window,
        shadow
    )
}

/// Checks the frame block of one shader, if it reads it (the storage block at set 0,
/// [`FRAME_BINDING`]), and returns the other blocks and whether it had one. No shader
/// may declare a uniform block: [`crate::render::frame::FRAME_DESCRIPTOR`] says why.
fn check_frame(what: &str, spirv: &[u32]) -> (Vec<Block>, bool) {
    let all = blocks(spirv);
    assert!(
        all.iter().all(|b| b.storage_class != UNIFORM),
        "{what}: a uniform block (lavapipe recompiles such shaders every frame)"
    );
    let (frame, others): (Vec<Block>, Vec<Block>) = all.into_iter().partition(|b| {
        b.storage_class == STORAGE_BUFFER && (b.set, b.binding) == (Some(0), Some(FRAME_BINDING))
    });
    assert!(frame.len() <= 1, "{what}: one frame block");
    for block in &frame {
        assert_eq!(
            block.offsets,
            frame_params_rust(),
            "{what}: FrameParams offsets"
        );
        // vec4/mat4 members: the struct ends 16 bytes after the last one.
        let last = block.offsets.last().copied().unwrap_or(0);
        assert_eq!(last as usize + 16, size_of::<FrameParams>(), "{what}: size");
    }
    (others, !frame.is_empty())
}

#[test]
fn the_ray_casting_shaders_read_the_structs_and_bindings_the_passes_write() {
    let mut frames_seen = 0;
    let mut coefficients_seen = 0;
    let mut shadow_seen = 0;
    let mut visibility_seen = 0;
    let mut pieces_seen = 0;
    for shader in RAYCAST_SHADERS {
        let what = format!("{:?} {}", shader.layout, shader.method);
        let spirvs = [shader.vertex, shader.fragment, shader.color_only_fragment];
        let shadows = [shader.shadows_fragment, shader.shadows_color_only_fragment];
        for spirv in spirvs.into_iter().chain(shadows.into_iter().flatten()) {
            let (others, frame) = check_frame(&what, spirv);
            frames_seen += usize::from(frame);
            for block in others {
                match block.storage_class {
                    // What a frame's later passes know (render::visibility): the work
                    // counters, the known depths after their header, the nearest
                    // distances.
                    STORAGE_BUFFER if block.set == Some(1) => {
                        let binding = block.binding.unwrap_or(u32::MAX);
                        let header = crate::render::visibility::KNOWN_DEPTH_HEADER as u32;
                        let expected = match binding {
                            0 | 2 => vec![0],
                            1 => vec![0, header],
                            other => panic!("{what}: visibility binding {other}"),
                        };
                        assert_eq!(block.offsets, expected, "{what}: binding {binding}");
                        visibility_seen += 1;
                    }
                    STORAGE_BUFFER if block.binding == Some(COEFFICIENTS_BINDING) => {
                        assert_eq!(block.set, Some(0), "{what}");
                        assert_eq!(block.offsets, [0], "{what}: float coeffs[]");
                        coefficients_seen += 1;
                    }
                    // The vertex shader's pieces (--proxy pieces): uint piece_words[].
                    STORAGE_BUFFER if block.binding == Some(PIECES_BINDING) => {
                        assert_eq!(block.set, Some(0), "{what}");
                        assert_eq!(block.offsets, [0], "{what}: uint piece_words[]");
                        pieces_seen += 1;
                    }
                    // The exact method's shadow rays (glsl/shadow.glsl): instances, boxes,
                    // the grid (GridHeader, then its cells) and its entries.
                    STORAGE_BUFFER => {
                        assert_eq!(shader.method, Method::Exact, "{what}: shadow buffers");
                        let binding = block.binding.unwrap_or(u32::MAX);
                        assert!(SHADOW_BINDINGS.contains(&binding), "{what}: {binding}");
                        assert_eq!(block.set, Some(0), "{what}");
                        let expected = if binding == SHADOW_BINDINGS[2] {
                            let mut header = offsets!(GridHeader: lo, cell, dims);
                            header.push(size_of::<GridHeader>() as u32);
                            header
                        } else {
                            vec![0]
                        };
                        assert_eq!(block.offsets, expected, "{what}: binding {binding}");
                        shadow_seen += 1;
                    }
                    // raycast.rs pushes one u32: hide_negative.
                    PUSH_CONSTANT => assert_eq!(block.offsets, [0], "{what}: push constants"),
                    other => panic!("{what}: unexpected block of storage class {other}"),
                }
            }
        }
    }
    assert!(visibility_seen > 0, "the visibility set is read");
    assert!(pieces_seen > 0, "the pieces are read");
    // Every vertex shader reads the coefficients (it hands them on as varyings), and the
    // robust methods' fragment shaders read them again.
    assert!(
        coefficients_seen >= RAYCAST_SHADERS.len(),
        "the coefficients are read"
    );
    assert!(
        frames_seen >= 2 * RAYCAST_SHADERS.len(),
        "the frame block is read"
    );
    // The two shadow-casting fragment shaders of every exact variant of the polynomial
    // glyph read the four shadow buffers; no other shader declares them.
    let exact = RAYCAST_SHADERS
        .iter()
        .filter(|s| s.method == Method::Exact && s.shape == ShapeShader::Polynomial)
        .count();
    let with_shadows = RAYCAST_SHADERS
        .iter()
        .filter(|s| s.shadows_fragment.is_some() && s.shadows_color_only_fragment.is_some())
        .count();
    assert_eq!(with_shadows, exact, "every exact variant casts shadows");
    assert_eq!(shadow_seen, 2 * 4 * exact, "the shadow buffers are read");
    for (what, spirv) in [
        ("raycast.vert", RAYCAST_VERTEX),
        ("impostor.frag", IMPOSTOR_FRAGMENT),
        ("mesh.vert", MESH_VERTEX),
        ("mesh.frag", MESH_FRAGMENT),
    ] {
        check_frame(what, spirv);
    }
}

#[test]
fn the_compute_ray_caster_reads_the_buffers_in_the_order_they_are_bound() {
    let push = offsets!(ComputeParams: hide_negative, slice, width, height);
    assert_eq!(size_of::<ComputeParams>(), 16);
    assert!(!COMPUTE_RAYCAST_SHADERS.is_empty());
    for shader in COMPUTE_RAYCAST_SHADERS {
        let what = format!("{:?} {} compute", shader.layout, shader.method);
        let (others, frame) = check_frame(&what, shader.spirv);
        assert!(frame, "{what}: reads the frame at binding {FRAME_BINDING}");
        let mut storage = Vec::new();
        for block in others {
            match block.storage_class {
                PUSH_CONSTANT => assert_eq!(block.offsets, push, "{what}: ComputeParams"),
                STORAGE_BUFFER => {
                    assert_eq!(block.set, Some(0), "{what}");
                    storage.push(block.binding.unwrap_or(u32::MAX));
                }
                other => panic!("{what}: unexpected block of storage class {other}"),
            }
        }
        // compute.rs binds the frame, then its five inputs and three outputs at
        // 1..BINDINGS, the coefficients first, at the ray caster's binding.
        storage.sort();
        let expected: Vec<u32> = (1..crate::render::compute::BINDINGS).collect();
        assert_eq!(storage, expected, "{what}: storage bindings");
        assert_eq!(expected[0], COEFFICIENTS_BINDING);
    }
}

#[test]
fn the_composing_draw_reads_the_compute_outputs_it_is_bound() {
    use crate::render::compute::{ComposeRegion, OUTPUT_BINDINGS};
    let push = offsets!(ComposeRegion: origin, row_length, pad);
    for (what, spirv) in [
        ("compose.frag", COMPOSE_FRAGMENT),
        ("compose.frag (colour only)", COMPOSE_COLOR_ONLY_FRAGMENT),
    ] {
        let mut storage = Vec::new();
        for block in blocks(spirv) {
            match block.storage_class {
                PUSH_CONSTANT => assert_eq!(block.offsets, push, "{what}: ComposeRegion"),
                STORAGE_BUFFER => {
                    assert_eq!(block.set, Some(0), "{what}");
                    storage.push(block.binding.unwrap_or(u32::MAX));
                }
                other => panic!("{what}: unexpected block of storage class {other}"),
            }
        }
        storage.sort();
        let expected: Vec<u32> = (0..OUTPUT_BINDINGS).collect();
        assert_eq!(storage, expected, "{what}: colours, distances, depths");
    }
    assert!(
        blocks(COMPOSE_VERTEX).is_empty(),
        "compose.vert reads nothing"
    );
}

#[test]
fn the_underlay_shaders_read_the_blocks_its_pass_writes() {
    let params = offsets!(UnderlayParams: world_to_voxel, dims, window);
    let push = offsets!(PlanePush: view_proj, origin, u, v);
    assert_eq!(
        size_of::<PlanePush>(),
        112,
        "within the 128 bytes every device offers"
    );
    let (mut params_seen, mut values_seen, mut push_seen) = (0, 0, 0);
    for (what, spirv) in [
        ("underlay.vert", UNDERLAY_VERTEX),
        ("underlay.frag", UNDERLAY_FRAGMENT),
    ] {
        for block in blocks(spirv) {
            assert_ne!(block.storage_class, UNIFORM, "{what}: a uniform block");
            match (block.storage_class, block.binding) {
                (STORAGE_BUFFER, Some(PARAMS_BINDING)) => {
                    assert_eq!(block.set, Some(0), "{what}");
                    assert_eq!(block.offsets, params, "{what}: UnderlayParams");
                    params_seen += 1;
                }
                (STORAGE_BUFFER, _) => {
                    assert_eq!(
                        (block.set, block.binding),
                        (Some(0), Some(VALUES_BINDING)),
                        "{what}"
                    );
                    assert_eq!(block.offsets, [0], "{what}: float values[]");
                    values_seen += 1;
                }
                (PUSH_CONSTANT, _) => {
                    assert_eq!(block.offsets, push, "{what}: PlanePush");
                    push_seen += 1;
                }
                (other, _) => panic!("{what}: unexpected block of storage class {other}"),
            }
        }
    }
    assert_eq!((params_seen, values_seen, push_seen), (2, 1, 1));
}

#[test]
fn the_underlay_receivers_read_the_batch_and_the_underlay_as_their_pass_binds_them() {
    use crate::render::shaders::UNDERLAY_RECEIVER_VERTEX;
    use crate::render::underlay_shadows::ReceiverPush;
    let params = offsets!(UnderlayParams: world_to_voxel, dims, window);
    // The plane follows the batch's word at byte 16.
    let plane = offset_of!(ReceiverPush, plane) as u32;
    assert_eq!(plane, 16);
    assert_eq!(
        size_of::<ReceiverPush>(),
        128,
        "the 128 bytes every device offers"
    );
    let push: Vec<u32> = offsets!(PlanePush: view_proj, origin, u, v)
        .into_iter()
        .map(|o| o + plane)
        .collect();
    let vertex = blocks(UNDERLAY_RECEIVER_VERTEX);
    let mut read: Vec<_> = vertex
        .iter()
        .map(|b| (b.storage_class, b.set, b.binding, b.offsets.clone()))
        .collect();
    read.sort();
    assert_eq!(
        read,
        [
            (PUSH_CONSTANT, None, None, push),
            (
                STORAGE_BUFFER,
                Some(1),
                Some(PARAMS_BINDING),
                params.clone()
            ),
        ],
        "the receiver's vertex shader"
    );
    check_receivers(
        "receiver",
        |shader| shader.receiver_fragment,
        |what, block| {
            if block.binding == Some(PARAMS_BINDING) {
                assert_eq!(block.offsets, params, "{what}: UnderlayParams");
            }
        },
        &[PARAMS_BINDING, VALUES_BINDING],
    );
}

/// Every exact polynomial variant has a receiver of this `kind` (`spirv_of`), and each
/// reads the frame block, the batch's word as a push constant, the batch's coefficients
/// and shadow grid in set 0 and, in set 1, the blocks at `set1` (each checked by
/// `check_set1`), as the receiver's pass binds them.
fn check_receivers(
    kind: &str,
    spirv_of: impl Fn(&RaycastShader) -> Option<&'static [u32]>,
    check_set1: impl Fn(&str, &Block),
    set1: &[u32],
) {
    let mut receivers = 0;
    for shader in RAYCAST_SHADERS {
        let Some(spirv) = spirv_of(shader) else {
            continue;
        };
        let what = format!("{:?} {kind}", shader.layout);
        let (others, frame) = check_frame(&what, spirv);
        assert!(frame, "{what}: reads the frame block");
        let mut seen = Vec::new();
        for block in others {
            match (block.storage_class, block.set, block.binding) {
                // The batch's word, as the ray-casting pipelines push it.
                (PUSH_CONSTANT, _, _) => assert_eq!(block.offsets, [0], "{what}"),
                (STORAGE_BUFFER, Some(set), Some(binding)) => {
                    if set == 1 {
                        check_set1(&what, &block);
                    }
                    seen.push((set, binding));
                }
                other => panic!("{what}: unexpected block {other:?}"),
            }
        }
        seen.sort();
        let mut expected = vec![(0, COEFFICIENTS_BINDING)];
        expected.extend(SHADOW_BINDINGS.map(|b| (0, b)));
        expected.extend(set1.iter().map(|&b| (1, b)));
        assert_eq!(seen, expected, "{what}: the bindings it reads");
        receivers += 1;
    }
    let exact = RAYCAST_SHADERS
        .iter()
        .filter(|s| s.method == Method::Exact && s.shape == ShapeShader::Polynomial)
        .count();
    assert_eq!(receivers, exact, "every exact variant has a {kind}");
}

#[test]
fn the_glyph_receivers_read_the_batch_and_the_hits_as_their_pass_binds_them() {
    // uvec4 hits_band, then the distances after the 16-byte header that headless.rs's
    // copy leaves.
    let header = crate::render::glyph_shadows::HITS_HEADER as u32;
    check_receivers(
        "glyph receiver",
        |shader| shader.glyph_receiver_fragment,
        |what, block| assert_eq!(block.offsets, [0, header], "{what}: Hits"),
        &[0],
    );
}
