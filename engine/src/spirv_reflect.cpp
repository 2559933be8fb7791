#include "spirv_reflect.h"

#include "gimg/engine/error.h"

#include <algorithm>
#include <string>
#include <unordered_map>

namespace gimg::detail {

namespace {

// SPIR-V opcodes, decorations and enums used below (SPIR-V 1.6 unified specification).
enum Op : std::uint32_t {
    OpEntryPoint = 15,
    OpExecutionMode = 16,
    OpTypeBool = 20,
    OpTypeInt = 21,
    OpTypeFloat = 22,
    OpTypeVector = 23,
    OpTypeMatrix = 24,
    OpTypeImage = 25,
    OpTypeSampler = 26,
    OpTypeSampledImage = 27,
    OpTypeArray = 28,
    OpTypeRuntimeArray = 29,
    OpTypeStruct = 30,
    OpTypePointer = 32,
    OpConstant = 43,
    OpSpecConstant = 50,
    OpVariable = 59,
    OpDecorate = 71,
    OpMemberDecorate = 72,
    OpExecutionModeId = 331,
    OpTypeForwardPointer = 39,
};
enum Decoration : std::uint32_t {
    DecBlock = 2,
    DecBufferBlock = 3,
    DecArrayStride = 6,
    DecMatrixStride = 7,
    DecBuiltIn = 11,
    DecBinding = 33,
    DecDescriptorSet = 34,
    DecOffset = 35,
};
enum StorageClass : std::uint32_t {
    UniformConstant = 0,
    Uniform = 2,
    PushConstant = 9,
    StorageBuffer = 12,
    PhysicalStorageBuffer = 5349,
};
constexpr std::uint32_t kExecutionModeLocalSize = 17, kExecutionModeLocalSizeId = 38;

struct TypeInfo {
    std::uint32_t op = 0;
    std::vector<std::uint32_t> operands;  // operands after the result id
};

struct Parser {
    explicit Parser(const Spirv& s) : shader(s) {}
    const Spirv& shader;
    std::unordered_map<std::uint32_t, TypeInfo> types;
    std::unordered_map<std::uint32_t, std::uint32_t> constants;  // id -> 32-bit value
    std::unordered_map<std::uint32_t, std::uint32_t> bindings, sets, array_strides;
    std::unordered_map<std::uint32_t, bool> block, buffer_block;
    // struct id -> member -> offset / matrix stride
    std::unordered_map<std::uint32_t, std::unordered_map<std::uint32_t, std::uint32_t>> offsets, matrix_strides;
    struct Variable {
        std::uint32_t type, id, storage;
    };
    std::vector<Variable> variables;

    [[noreturn]] void fail(const std::string& why) const {
        throw Error(ErrorKind::InvalidArgument, std::string("shader ") + shader.name + ": " + why);
    }

    // Byte size of a type inside a push-constant block (explicit layout: offsets and strides).
    std::uint32_t size_of(std::uint32_t type_id, std::uint32_t matrix_stride = 0, int depth = 0) const {
        if (depth > 16) fail("type nesting too deep");
        auto it = types.find(type_id);
        if (it == types.end()) fail("unknown type id " + std::to_string(type_id));
        const TypeInfo& t = it->second;
        switch (t.op) {
            case OpTypeBool:
                return 4;
            case OpTypeInt:
            case OpTypeFloat:
                return t.operands.at(0) / 8;
            case OpTypeVector:
                return t.operands.at(1) * size_of(t.operands.at(0), 0, depth + 1);
            case OpTypeMatrix:
                return t.operands.at(1) * (matrix_stride ? matrix_stride : size_of(t.operands.at(0), 0, depth + 1));
            case OpTypeArray: {
                auto stride = array_strides.find(type_id);
                auto length = constants.find(t.operands.at(1));
                if (length == constants.end()) fail("array length is not a constant");
                std::uint32_t elem =
                    stride != array_strides.end() ? stride->second : size_of(t.operands.at(0), 0, depth + 1);
                return elem * length->second;
            }
            case OpTypeStruct: {
                std::uint32_t size = 0;
                auto offs = offsets.find(type_id);
                auto strides = matrix_strides.find(type_id);
                for (std::uint32_t m = 0; m < t.operands.size(); ++m) {
                    std::uint32_t off = 0;
                    if (offs != offsets.end()) {
                        auto o = offs->second.find(m);
                        if (o != offs->second.end()) off = o->second;
                    }
                    std::uint32_t ms = 0;
                    if (strides != matrix_strides.end()) {
                        auto s = strides->second.find(m);
                        if (s != strides->second.end()) ms = s->second;
                    }
                    size = std::max(size, off + size_of(t.operands[m], ms, depth + 1));
                }
                return size;
            }
            case OpTypePointer:
                return 8;  // buffer device address
            default:
                fail("unsupported type in push-constant block (opcode " + std::to_string(t.op) + ")");
        }
    }

    VkDescriptorType descriptor_type(const Variable& v) const {
        const TypeInfo& ptr = types.at(v.type);
        std::uint32_t pointee = ptr.operands.at(1);
        const TypeInfo* t = &types.at(pointee);
        if (t->op == OpTypeArray || t->op == OpTypeRuntimeArray)
            fail("descriptor arrays are not supported (binding " + std::to_string(bindings.at(v.id)) + ")");
        if (v.storage == StorageBuffer) return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        if (v.storage == Uniform)
            return buffer_block.count(pointee) ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER : VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        if (t->op == OpTypeSampledImage) return VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        if (t->op == OpTypeImage) {
            std::uint32_t sampled = t->operands.at(5);
            return sampled == 2 ? VK_DESCRIPTOR_TYPE_STORAGE_IMAGE : VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
        }
        if (t->op == OpTypeSampler) return VK_DESCRIPTOR_TYPE_SAMPLER;
        fail("unsupported descriptor type at binding " + std::to_string(bindings.at(v.id)));
    }
};

VkShaderStageFlagBits stage_of(std::uint32_t execution_model) {
    switch (execution_model) {
        case 0:
            return VK_SHADER_STAGE_VERTEX_BIT;
        case 3:
            return VK_SHADER_STAGE_GEOMETRY_BIT;
        case 4:
            return VK_SHADER_STAGE_FRAGMENT_BIT;
        case 5:
            return VK_SHADER_STAGE_COMPUTE_BIT;
        default:
            return VK_SHADER_STAGE_ALL;
    }
}

}  // namespace

ShaderReflection reflect_spirv(const Spirv& shader) {
    Parser p(shader);
    const std::uint32_t* w = shader.words;
    const std::size_t n = shader.word_count;
    if (!w || n < 5 || w[0] != 0x07230203u) p.fail("not a SPIR-V module");
    ShaderReflection out;
    bool have_entry = false;
    std::array<std::uint32_t, 3> local_size_ids{0, 0, 0};
    bool local_size_by_id = false;
    for (std::size_t i = 5; i < n;) {
        std::uint32_t count = w[i] >> 16, op = w[i] & 0xffffu;
        if (count == 0 || i + count > n) p.fail("truncated instruction");
        const std::uint32_t* a = w + i + 1;  // operands
        std::uint32_t na = count - 1;
        switch (op) {
            case OpEntryPoint:
                if (!have_entry) out.stage = stage_of(a[0]), have_entry = true;
                break;
            case OpExecutionMode:
                if (na >= 5 && a[1] == kExecutionModeLocalSize) out.local_size = {a[2], a[3], a[4]};
                break;
            case OpExecutionModeId:
                if (na >= 5 && a[1] == kExecutionModeLocalSizeId) {
                    local_size_ids = {a[2], a[3], a[4]};
                    local_size_by_id = true;
                }
                break;
            case OpDecorate:
                if (na >= 3 && a[1] == DecBinding) p.bindings[a[0]] = a[2];
                if (na >= 3 && a[1] == DecDescriptorSet) p.sets[a[0]] = a[2];
                if (na >= 3 && a[1] == DecArrayStride) p.array_strides[a[0]] = a[2];
                if (na >= 2 && a[1] == DecBlock) p.block[a[0]] = true;
                if (na >= 2 && a[1] == DecBufferBlock) p.buffer_block[a[0]] = true;
                break;
            case OpMemberDecorate:
                if (na >= 4 && a[2] == DecOffset) p.offsets[a[0]][a[1]] = a[3];
                if (na >= 4 && a[2] == DecMatrixStride) p.matrix_strides[a[0]][a[1]] = a[3];
                break;
            case OpTypeBool:
            case OpTypeInt:
            case OpTypeFloat:
            case OpTypeVector:
            case OpTypeMatrix:
            case OpTypeImage:
            case OpTypeSampler:
            case OpTypeSampledImage:
            case OpTypeArray:
            case OpTypeRuntimeArray:
            case OpTypeStruct:
            case OpTypePointer:
                if (na >= 1) p.types[a[0]] = TypeInfo{op, std::vector<std::uint32_t>(a + 1, a + na)};
                break;
            case OpConstant:
            case OpSpecConstant:
                if (na >= 3) p.constants[a[1]] = a[2];
                break;
            case OpVariable:
                if (na >= 3) p.variables.push_back({a[0], a[1], a[2]});
                break;
            default:
                break;
        }
        i += count;
    }
    if (!have_entry) p.fail("no entry point");
    if (local_size_by_id) {
        for (int k = 0; k < 3; ++k) {
            auto c = p.constants.find(local_size_ids[k]);
            if (c == p.constants.end()) p.fail("local size is not a constant");
            out.local_size[k] = c->second;
        }
    }
    for (const auto& v : p.variables) {
        if (v.storage == PushConstant) {
            std::uint32_t pointee = p.types.at(v.type).operands.at(1);
            out.push_constant_bytes = std::max(out.push_constant_bytes, p.size_of(pointee));
            continue;
        }
        if (v.storage != UniformConstant && v.storage != Uniform && v.storage != StorageBuffer) continue;
        auto b = p.bindings.find(v.id);
        if (b == p.bindings.end()) continue;
        auto s = p.sets.find(v.id);
        if (s != p.sets.end() && s->second != 0)
            p.fail("uses descriptor set " + std::to_string(s->second) + "; gimg binds everything in set 0");
        out.bindings.push_back({b->second, p.descriptor_type(v)});
    }
    std::sort(out.bindings.begin(), out.bindings.end(),
              [](const ReflectedBinding& x, const ReflectedBinding& y) { return x.binding < y.binding; });
    for (std::size_t i = 1; i < out.bindings.size(); ++i)
        if (out.bindings[i].binding == out.bindings[i - 1].binding)
            p.fail("two resources share binding " + std::to_string(out.bindings[i].binding));
    return out;
}

}  // namespace gimg::detail
