//! What a compiled SPIR-V module says about its interface: struct member offsets, array
//! strides, descriptor bindings, and the constants a shader stores. The interface tests
//! (`shader_interface.rs`) hold the Rust records and codes against it.

use std::collections::HashMap;

use rspirv::dr::{Instruction, Module, Operand};
use rspirv::spirv::{Decoration, Op, Word};

pub(crate) struct Reflection {
    module: Module,
}

impl Reflection {
    pub(crate) fn of(spirv: &[u8]) -> Self {
        let module =
            rspirv::dr::load_words(crate::shaders::words(spirv)).expect("the build wrote valid SPIR-V");
        Self { module }
    }

    /// Every type or variable that `OpName` calls `name`.
    fn ids_named(&self, name: &str) -> Vec<Word> {
        let named =
            |i: &&Instruction| i.class.opcode == Op::Name && i.operands[1].unwrap_literal_string() == name;
        self.module.debug_names.iter().filter(named).map(|i| i.operands[0].unwrap_id_ref()).collect()
    }

    /// The variables called `name`, and those of a type called `name`: a block declared
    /// without an instance name has a nameless variable.
    fn variables_named(&self, name: &str) -> Vec<Word> {
        let named = self.ids_named(name);
        let pointers: Vec<Word> = self
            .module
            .types_global_values
            .iter()
            .filter(|i| i.class.opcode == Op::TypePointer && named.contains(&i.operands[1].unwrap_id_ref()))
            .filter_map(|i| i.result_id)
            .collect();
        let variables = self.module.types_global_values.iter().filter(|i| i.class.opcode == Op::Variable);
        let of_name = |i: &Instruction| {
            let id = i.result_id?;
            (named.contains(&id) || i.result_type.is_some_and(|t| pointers.contains(&t))).then_some(id)
        };
        variables.filter_map(of_name).collect()
    }

    fn member_names(&self, id: Word) -> HashMap<u32, String> {
        let of_id =
            |i: &&Instruction| i.class.opcode == Op::MemberName && i.operands[0].unwrap_id_ref() == id;
        let entry = |i: &Instruction| {
            (i.operands[1].unwrap_literal_bit32(), i.operands[2].unwrap_literal_string().to_owned())
        };
        self.module.debug_names.iter().filter(of_id).map(entry).collect()
    }

    /// The value of decoration `decoration` on `id`, when it carries one.
    fn decoration(&self, id: Word, decoration: Decoration) -> Option<u32> {
        self.module.annotations.iter().find_map(|i| match i.operands.as_slice() {
            [Operand::IdRef(target), Operand::Decoration(d), Operand::LiteralBit32(value)]
                if i.class.opcode == Op::Decorate && *target == id && *d == decoration =>
            {
                Some(*value)
            }
            _ => None,
        })
    }

    /// The struct called `name` whose members carry offsets (glslang may also emit copies
    /// without a layout), as `(member name, offset)` in member order.
    pub(crate) fn member_offsets(&self, name: &str) -> Vec<(String, u32)> {
        let laid_out = self.ids_named(name).into_iter().find_map(|id| {
            let names = self.member_names(id);
            let mut offsets: Vec<(u32, u32)> = self.member_offset_decorations(id);
            offsets.sort();
            (!offsets.is_empty())
                .then(|| offsets.into_iter().map(|(m, offset)| (names[&m].clone(), offset)).collect())
        });
        laid_out.unwrap_or_else(|| panic!("no laid-out struct `{name}` in the module"))
    }

    fn member_offset_decorations(&self, id: Word) -> Vec<(u32, u32)> {
        let offset = |i: &Instruction| match i.operands.as_slice() {
            [
                Operand::IdRef(target),
                Operand::LiteralBit32(member),
                Operand::Decoration(Decoration::Offset),
                Operand::LiteralBit32(offset),
            ] if i.class.opcode == Op::MemberDecorate && *target == id => Some((*member, *offset)),
            _ => None,
        };
        self.module.annotations.iter().filter_map(offset).collect()
    }

    /// The stride of the (runtime) arrays of the struct called `name`: its size in std430.
    pub(crate) fn array_stride_of(&self, name: &str) -> u32 {
        let elements = self.ids_named(name);
        let is_array_of = |i: &&Instruction| {
            matches!(i.class.opcode, Op::TypeRuntimeArray | Op::TypeArray)
                && elements.contains(&i.operands[0].unwrap_id_ref())
        };
        let array = self.module.types_global_values.iter().find(is_array_of);
        let array = array.unwrap_or_else(|| panic!("no array of `{name}` in the module"));
        self.decoration(array.result_id.expect("types have ids"), Decoration::ArrayStride)
            .expect("arrays carry a stride")
    }

    /// The bound variable called `name` (a variable or a block's type), if the module has one.
    fn bound_variable(&self, name: &str) -> Option<Word> {
        self.variables_named(name).into_iter().find(|&id| self.decoration(id, Decoration::Binding).is_some())
    }

    /// Whether the module binds a resource called `name`.
    pub(crate) fn has_binding(&self, name: &str) -> bool {
        self.bound_variable(name).is_some()
    }

    /// `(set, binding)` of the resource called `name` (a variable or a block's type).
    pub(crate) fn binding_of(&self, name: &str) -> (u32, u32) {
        let variable = self.bound_variable(name);
        let variable = variable.unwrap_or_else(|| panic!("no bound variable `{name}` in the module"));
        let set = self.decoration(variable, Decoration::DescriptorSet).expect("bound variables carry a set");
        (set, self.decoration(variable, Decoration::Binding).expect("checked above"))
    }

    /// The integer constants stored through `array[index]` of the block called `block`, by
    /// index: what a probe shader writes with `array[i] = CONSTANT`.
    pub(crate) fn stored_constants(&self, block: &str) -> HashMap<u32, u32> {
        let constants: HashMap<Word, u32> = self
            .module
            .types_global_values
            .iter()
            .filter(|i| i.class.opcode == Op::Constant)
            .filter_map(|i| Some((i.result_id?, i.operands.first()?.unwrap_literal_bit32())))
            .collect();
        let variables = self.variables_named(block);
        let instructions = self.module.functions.iter().flat_map(|f| &f.blocks).flat_map(|b| &b.instructions);
        let mut element_index: HashMap<Word, u32> = HashMap::new();
        let mut stored = HashMap::new();
        for instruction in instructions {
            match instruction.class.opcode {
                Op::AccessChain if variables.contains(&instruction.operands[0].unwrap_id_ref()) => {
                    let last = instruction.operands.last().expect("a chain has indices").unwrap_id_ref();
                    element_index.insert(instruction.result_id.expect("chains have ids"), constants[&last]);
                }
                Op::Store => {
                    let (pointer, object) =
                        (instruction.operands[0].unwrap_id_ref(), instruction.operands[1].unwrap_id_ref());
                    if let (Some(&index), Some(&value)) =
                        (element_index.get(&pointer), constants.get(&object))
                    {
                        stored.insert(index, value);
                    }
                }
                _ => {}
            }
        }
        stored
    }
}
