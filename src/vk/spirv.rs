//! Fragment shaders for a device without `fragmentStoresAndAtomics`.
//!
//! The ray-casting fragment shaders write storage buffers: the work counters and the
//! known depths of culled frames (render::visibility). Those writes run only in pipelines
//! whose `VISIBILITY` specialisation constant is true, but Vulkan asks more of a device
//! that did not enable `fragmentStoresAndAtomics`: every storage buffer a fragment shader
//! declares must be decorated `NonWritable` (VUID-RuntimeSpirv-NonWritable-06340), and
//! a store through it would be invalid even where it never runs. A host engine's device
//! may lack the feature (the engine component asked only for dynamic rendering), so its
//! fragment modules are rewritten here before they are created: every store into a
//! storage buffer is removed, every atomic operation on one becomes a load of the same
//! value type (the code that held them is dead under `VISIBILITY = false`, which such a
//! device always gets, but it must stay valid SPIR-V), and every member of a storage
//! buffer's block is decorated `NonWritable`.
//!
//! The rewrite works on the instruction stream (word count and opcode in each first word),
//! with opcodes from the SPIR-V specification's unified grammar.

/// SPIR-V's magic number, the first word of a module.
const MAGIC: u32 = 0x0723_0203;
/// Words of the module header before the first instruction.
const HEADER_WORDS: usize = 5;

const OP_TYPE_STRUCT: u32 = 30;
const OP_TYPE_POINTER: u32 = 32;
const OP_VARIABLE: u32 = 59;
const OP_LOAD: u32 = 61;
const OP_STORE: u32 = 62;
const OP_COPY_MEMORY: u32 = 63;
const OP_DECORATE: u32 = 71;
const OP_MEMBER_DECORATE: u32 = 72;
const OP_ATOMIC_STORE: u32 = 228;
/// OpAtomicExchange to OpAtomicXor: result type, result, pointer, then operands.
const OP_ATOMICS_WITH_RESULT: std::ops::RangeInclusive<u32> = 229..=242;
/// OpAtomicFMinEXT, OpAtomicFMaxEXT and OpAtomicFAddEXT (same layout).
const OP_ATOMICS_FLOAT: [u32; 3] = [5614, 5615, 6035];

const STORAGE_CLASS_UNIFORM: u32 = 2;
const STORAGE_CLASS_STORAGE_BUFFER: u32 = 12;
const DECORATION_BUFFER_BLOCK: u32 = 3;
const DECORATION_NON_WRITABLE: u32 = 24;

/// Each instruction of `words` after the header: where it starts, its opcode and its
/// word count; it stops at an instruction of no words or one longer than the words left.
pub(crate) fn walk(words: &[u32]) -> impl Iterator<Item = (usize, u32, usize)> + '_ {
    let mut at = HEADER_WORDS;
    std::iter::from_fn(move || {
        let first = *words.get(at)?;
        let count = (first >> 16) as usize;
        if count == 0 || at + count > words.len() {
            return None;
        }
        let this = (at, first & 0xffff, count);
        at += count;
        Some(this)
    })
}

/// Every instruction of a module: its opcode and its words (the first included); `None`
/// where the words are not whole instructions.
fn instructions(words: &[u32]) -> Option<Vec<(u32, &[u32])>> {
    let mut end = HEADER_WORDS;
    let list: Vec<_> = walk(words)
        .map(|(at, opcode, count)| {
            end = at + count;
            (opcode, &words[at..at + count])
        })
        .collect();
    (words.len() >= HEADER_WORDS && end == words.len()).then_some(list)
}

/// `spirv` with no write into a storage buffer and every storage buffer's members
/// decorated `NonWritable`, as a device without `fragmentStoresAndAtomics` takes a
/// fragment shader; `None` where `spirv` is not a module of whole instructions.
pub(crate) fn without_buffer_writes(spirv: &[u32]) -> Option<Vec<u32>> {
    if spirv.len() < HEADER_WORDS || spirv[0] != MAGIC {
        return None;
    }
    let list = instructions(spirv)?;
    let mut structs = std::collections::HashMap::new(); // struct id -> member count
    let mut buffer_blocks = std::collections::HashSet::new(); // BufferBlock-decorated ids
    let mut non_writable = std::collections::HashSet::new(); // (struct, member)
    let mut pointers = std::collections::HashMap::new(); // pointer type -> (class, pointee)
    let mut result_types = std::collections::HashMap::new(); // id -> its type id
    for &(opcode, words) in &list {
        match opcode {
            OP_TYPE_STRUCT => {
                structs.insert(words[1], words.len() - 2);
            }
            OP_TYPE_POINTER if words.len() >= 4 => {
                pointers.insert(words[1], (words[2], words[3]));
            }
            OP_DECORATE if words.len() >= 3 && words[2] == DECORATION_BUFFER_BLOCK => {
                buffer_blocks.insert(words[1]);
            }
            OP_MEMBER_DECORATE if words.len() >= 4 && words[3] == DECORATION_NON_WRITABLE => {
                non_writable.insert((words[1], words[2]));
            }
            _ => {}
        }
        if has_result_type(opcode) && words.len() >= 3 {
            result_types.insert(words[2], words[1]);
        }
    }
    // A pointer into a storage buffer: of the StorageBuffer class, or of the Uniform
    // class into a BufferBlock (SPIR-V before 1.3).
    let is_buffer_pointer_type = |pointer_type: u32| {
        pointers
            .get(&pointer_type)
            .is_some_and(|&(class, pointee)| {
                class == STORAGE_CLASS_STORAGE_BUFFER
                    || (class == STORAGE_CLASS_UNIFORM && buffer_blocks.contains(&pointee))
            })
    };
    let points_into_buffer = |id: u32| {
        result_types
            .get(&id)
            .is_some_and(|&ty| is_buffer_pointer_type(ty))
    };
    // The blocks of the storage buffers the module declares.
    let mut blocks: Vec<u32> = list
        .iter()
        .filter(|(opcode, words)| *opcode == OP_VARIABLE && is_buffer_pointer_type(words[1]))
        .filter_map(|(_, words)| pointers.get(&words[1]).map(|&(_, pointee)| pointee))
        .filter(|pointee| structs.contains_key(pointee))
        .collect();
    blocks.sort_unstable();
    blocks.dedup();
    let decorations: Vec<u32> = blocks
        .iter()
        .flat_map(|&block| (0..structs[&block] as u32).map(move |member| (block, member)))
        .filter(|key| !non_writable.contains(key))
        .flat_map(|(block, member)| {
            [
                (4 << 16) | OP_MEMBER_DECORATE,
                block,
                member,
                DECORATION_NON_WRITABLE,
            ]
        })
        .collect();

    let mut out = Vec::with_capacity(spirv.len() + decorations.len());
    out.extend_from_slice(&spirv[..HEADER_WORDS]);
    let mut decorated = false;
    for &(opcode, words) in &list {
        if !decorated && matches!(opcode, OP_DECORATE | OP_MEMBER_DECORATE) {
            out.extend_from_slice(&decorations);
            decorated = true;
        }
        let writes_through =
            |pointer: Option<&u32>| pointer.is_some_and(|&p| points_into_buffer(p));
        match opcode {
            OP_STORE | OP_ATOMIC_STORE | OP_COPY_MEMORY if writes_through(words.get(1)) => {}
            _ if (OP_ATOMICS_WITH_RESULT.contains(&opcode)
                || OP_ATOMICS_FLOAT.contains(&opcode))
                && writes_through(words.get(3)) =>
            {
                out.extend_from_slice(&[(4 << 16) | OP_LOAD, words[1], words[2], words[3]]);
            }
            _ => out.extend_from_slice(words),
        }
    }
    // A module with storage buffers has decorations (their Block and offsets).
    (decorated || decorations.is_empty()).then_some(out)
}

/// Whether instructions of `opcode` have a result type and a result id (words 1 and 2):
/// those this rewrite reads pointer types from (variables, access chains, function
/// parameters, loads of pointers, copies and selections of pointers).
fn has_result_type(opcode: u32) -> bool {
    matches!(
        opcode,
        OP_VARIABLE
            | 55  // OpFunctionParameter
            | 65  // OpAccessChain
            | 66  // OpInBoundsAccessChain
            | 67  // OpPtrAccessChain
            | 70  // OpInBoundsPtrAccessChain
            | 83  // OpCopyObject
            | 169 // OpSelect
            | 245 // OpPhi
            | 57 // OpFunctionCall
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The words of every instruction of `spirv` with `opcode`.
    fn with_opcode(spirv: &[u32], opcode: u32) -> Vec<Vec<u32>> {
        instructions(spirv)
            .unwrap()
            .into_iter()
            .filter(|(op, _)| *op == opcode)
            .map(|(_, words)| words.to_vec())
            .collect()
    }

    #[test]
    fn the_exact_fragment_shader_keeps_no_buffer_write() {
        let shader = crate::render::shaders::RAYCAST_SHADERS
            .iter()
            .find(|s| s.method == crate::render::Method::Exact)
            .expect("an exact shader");
        let before = shader.fragment;
        let after = without_buffer_writes(before).expect("a module");
        // The shader writes buffers (counters, known depths) and has atomics.
        let atomics = |spirv: &[u32]| {
            instructions(spirv)
                .unwrap()
                .iter()
                .filter(|(op, _)| OP_ATOMICS_WITH_RESULT.contains(op))
                .count()
        };
        assert!(atomics(before) > 0, "the shader has atomics to remove");
        assert_eq!(atomics(&after), 0);
        // Every store left writes a function variable or an output, never a buffer.
        let list = instructions(&after).unwrap();
        let stores = with_opcode(&after, OP_STORE).len();
        assert!(stores > 0 && stores < with_opcode(before, OP_STORE).len());
        // Every member of the buffers' blocks is NonWritable, once.
        let decorated: Vec<_> = with_opcode(&after, OP_MEMBER_DECORATE)
            .into_iter()
            .filter(|w| w[3] == DECORATION_NON_WRITABLE)
            .map(|w| (w[1], w[2]))
            .collect();
        let unique: std::collections::HashSet<_> = decorated.iter().collect();
        assert_eq!(unique.len(), decorated.len(), "a member decorated twice");
        let variables = list
            .iter()
            .filter(|(op, w)| *op == OP_VARIABLE && w[3] == STORAGE_CLASS_STORAGE_BUFFER)
            .count();
        assert!(
            variables >= 3,
            "counters, known depths, nearest distances: {variables}"
        );
        assert!(unique.len() >= variables);
        // Applied twice, it changes nothing more.
        assert_eq!(without_buffer_writes(&after).unwrap(), after);
    }

    #[test]
    fn what_is_not_a_module_is_refused() {
        assert!(without_buffer_writes(&[]).is_none());
        assert!(without_buffer_writes(&[1, 2, 3, 4, 5, 6]).is_none());
        // An instruction longer than the words left.
        assert!(without_buffer_writes(&[MAGIC, 0x0001_0300, 0, 10, 0, (9 << 16) | 17]).is_none());
    }
}
