//! Shader modules whose float arithmetic the driver must not fuse or reorder.
//!
//! The backend's WGSL follows core's order of operations so that it rounds as the CPU backend
//! does (SPEC 7: the same pixels). A Vulkan driver is free to contract `a * b + c` into a fused
//! multiply-add and to reassociate sums unless an operation carries SPIR-V's `NoContraction`
//! decoration, and WGSL cannot ask for it. Mesa's lavapipe does neither; NVIDIA's driver does
//! both (measured on an H200, driver 580.159.04: depths one ULP apart in every transformed
//! draw, a sprite's `u` a rounding error below a texel edge, ADDSIGNED ties one step over;
//! docs/PERFORMANCE.md). So where the device takes SPIR-V as it is
//! (`Features::PASSTHROUGH_SHADERS`, a Vulkan device), the WGSL is compiled here with naga,
//! every float arithmetic instruction decorated `NoContraction`, and handed to the driver
//! unchanged; elsewhere it goes through wgpu as WGSL.

use std::borrow::Cow;

use naga::back::spv;

/// SPIR-V opcodes whose result is float arithmetic that `NoContraction` keeps apart: OpFNegate,
/// OpFAdd, OpFSub, OpFMul, OpFDiv, OpFRem, OpFMod, OpVectorTimesScalar, OpMatrixTimesScalar,
/// OpVectorTimesMatrix, OpMatrixTimesVector, OpMatrixTimesMatrix, OpDot.
const FLOAT_ARITHMETIC: [u32; 13] = [
    127, 129, 131, 133, 136, 140, 141, 142, 143, 144, 145, 146, 148,
];

/// OpDecorate, and the decoration NoContraction.
const OP_DECORATE: u32 = 71;
const NO_CONTRACTION: u32 = 42;

/// Opcodes of the annotation section (OpDecorate, OpMemberDecorate, OpDecorationGroup,
/// OpGroupDecorate, OpGroupMemberDecorate, OpDecorateId, OpDecorateString,
/// OpMemberDecorateString): the decorations are added after the last of them.
const ANNOTATIONS: [u32; 8] = [71, 72, 73, 74, 75, 332, 5632, 5633];

/// OpFunction: the annotation section lies before the first.
const OP_FUNCTION: u32 = 54;

/// Whether a device on `backend` with `features` takes the modules as SPIR-V without
/// contraction: a Vulkan device with `Features::PASSTHROUGH_SHADERS` (on Metal and D3D12 the
/// feature passes MSL and DXIL through instead).
pub(crate) fn takes_spirv(backend: wgpu::Backend, features: wgpu::Features) -> bool {
    backend == wgpu::Backend::Vulkan && features.contains(wgpu::Features::PASSTHROUGH_SHADERS)
}

/// The module of `wgsl`: with `spirv` ([`takes_spirv`]), compiled without contraction (see the
/// module's doc), else by wgpu. A module naga cannot compile goes to wgpu as it is, which
/// reports the error as for any other module.
#[allow(unsafe_code)] // The SPIR-V passthrough.
pub(crate) fn create(
    device: &wgpu::Device,
    spirv: bool,
    label: &str,
    wgsl: &str,
) -> wgpu::ShaderModule {
    if spirv && let Some((words, entry_points)) = no_contraction_spirv(wgsl) {
        let entry_points: Vec<_> = entry_points
            .into_iter()
            .map(|name| wgpu::PassthroughShaderEntryPoint {
                name: Cow::Owned(name),
                workgroup_size: (0, 0, 0), // read from the SPIR-V
            })
            .collect();
        let desc = wgpu::ShaderModuleDescriptorPassthrough {
            label: Some(label),
            entry_points: Cow::Owned(entry_points),
            spirv: Some(Cow::Owned(words)),
            ..Default::default()
        };
        // SAFETY: the SPIR-V is naga's translation of WGSL that naga validated, with the bounds
        // checks wgpu's own Vulkan translation applies, and decorations added that change no
        // result but the rounding order the WGSL already states.
        return unsafe { device.create_shader_module_passthrough(desc) };
    }
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(wgsl.into()),
    })
}

/// `wgsl` as SPIR-V with every float arithmetic instruction decorated `NoContraction`, and
/// its entry points' names; `None` where naga cannot parse, validate or translate it.
fn no_contraction_spirv(wgsl: &str) -> Option<(Vec<u32>, Vec<String>)> {
    let (words, names) = translate(wgsl)?;
    Some((no_contraction(&words)?, names))
}

/// `wgsl` as naga translates it to SPIR-V for Vulkan (the options of wgpu's own Vulkan
/// translation on a device without robust buffer and image access), and its entry points'
/// names.
fn translate(wgsl: &str) -> Option<(Vec<u32>, Vec<String>)> {
    let module = naga::front::wgsl::parse_str(wgsl).ok()?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .ok()?;
    let restrict = naga::proc::BoundsCheckPolicy::Restrict;
    let options = spv::Options {
        flags: spv::WriterFlags::LABEL_VARYINGS | spv::WriterFlags::FORCE_POINT_SIZE,
        bounds_check_policies: naga::proc::BoundsCheckPolicies {
            index: restrict,
            buffer: restrict,
            image_load: restrict,
            binding_array: naga::proc::BoundsCheckPolicy::Unchecked,
        },
        ..spv::Options::default()
    };
    let words = spv::write_vec(&module, &info, &options, None).ok()?;
    let names = module.entry_points.iter().map(|e| e.name.clone()).collect();
    Some((words, names))
}

/// `words`, a SPIR-V module, with an `OpDecorate %id NoContraction` for the result of every
/// float arithmetic instruction ([`FLOAT_ARITHMETIC`]), placed after the last annotation
/// before the first function; `None` where the module is malformed or has no annotation.
fn no_contraction(words: &[u32]) -> Option<Vec<u32>> {
    const HEADER: usize = 5;
    let mut results = Vec::new();
    let mut insert_at = None;
    let mut at = HEADER;
    let mut in_functions = false;
    while at < words.len() {
        let (count, opcode) = ((words[at] >> 16) as usize, words[at] & 0xFFFF);
        if count == 0 || at + count > words.len() {
            return None;
        }
        if opcode == OP_FUNCTION {
            in_functions = true;
        }
        if !in_functions && ANNOTATIONS.contains(&opcode) {
            insert_at = Some(at + count);
        }
        if FLOAT_ARITHMETIC.contains(&opcode) && count >= 3 {
            results.push(words[at + 2]); // result type, then result id
        }
        at += count;
    }
    let insert_at = insert_at?;
    let mut out = Vec::with_capacity(words.len() + 3 * results.len());
    out.extend_from_slice(&words[..insert_at]);
    for id in results {
        out.extend_from_slice(&[(3 << 16) | OP_DECORATE, id, NO_CONTRACTION]);
    }
    out.extend_from_slice(&words[insert_at..]);
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every float multiply and add of a module gets one decoration, among the annotations;
    /// the instructions themselves are kept word for word.
    #[test]
    fn float_arithmetic_is_decorated_no_contraction() {
        let wgsl = "@group(0) @binding(0) var<storage, read_write> v: array<f32>;
            @compute @workgroup_size(1) fn main() { v[0] = v[1] * v[2] + v[3]; }";
        let (words, names) = no_contraction_spirv(wgsl).expect("naga translates it");
        assert_eq!(names, ["main"]);
        let instructions = |w: &[u32]| {
            let mut out = Vec::new();
            let mut at = 5;
            while at < w.len() {
                let count = (w[at] >> 16) as usize;
                out.push(w[at..at + count].to_vec());
                at += count;
            }
            out
        };
        let all = instructions(&words);
        let id_of = |op: u32| {
            all.iter()
                .find(|i| i[0] & 0xFFFF == op)
                .map(|i| i[2])
                .expect("the op")
        };
        let (mul, add) = (id_of(133), id_of(129));
        let decorated: Vec<u32> = all
            .iter()
            .filter(|i| i[0] & 0xFFFF == OP_DECORATE && i.get(2) == Some(&NO_CONTRACTION))
            .map(|i| i[1])
            .collect();
        assert_eq!(decorated, [mul, add]);
        let function = all
            .iter()
            .position(|i| i[0] & 0xFFFF == OP_FUNCTION)
            .unwrap();
        let last = all
            .iter()
            .rposition(|i| i[0] & 0xFFFF == OP_DECORATE)
            .unwrap();
        assert!(last < function, "annotations come before the functions");
        // Nothing else changed: removing the decorations gives naga's module back.
        let plain: Vec<Vec<u32>> = all
            .into_iter()
            .filter(|i| !(i[0] & 0xFFFF == OP_DECORATE && i.get(2) == Some(&NO_CONTRACTION)))
            .collect();
        let (original, _) = translate(wgsl).unwrap();
        assert_eq!(plain, instructions(&original));
    }

    /// Only a Vulkan device takes SPIR-V through the passthrough: on Metal and D3D12 the same
    /// feature means MSL and DXIL.
    #[test]
    fn only_vulkan_takes_spirv() {
        let pass = wgpu::Features::PASSTHROUGH_SHADERS;
        assert!(takes_spirv(wgpu::Backend::Vulkan, pass));
        assert!(!takes_spirv(wgpu::Backend::Vulkan, wgpu::Features::empty()));
        assert!(!takes_spirv(wgpu::Backend::Metal, pass));
        assert!(!takes_spirv(wgpu::Backend::Dx12, pass));
    }

    #[test]
    fn a_malformed_module_is_refused() {
        assert_eq!(no_contraction(&[0x0723_0203, 0, 0, 0, 0, 0]), None);
        assert_eq!(no_contraction(&[0x0723_0203, 0, 0, 0, 0, 5 << 16]), None);
    }
}
