// The per-patch buffers, read by device address: the records of layout.glsl and the colour
// neighbour lists (src/interpolate_color.rs). Shared by bindings.glsl and the kernels that
// walk a patch set, which compile outside the ray-tracing stages too.
#ifndef POINTRAY_PATCH_BUFFERS_GLSL
#define POINTRAY_PATCH_BUFFERS_GLSL

#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require

#include "layout.glsl"
#include "unpacked_patch.glsl"

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer HotPatches { PatchHot records[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer ColdPatches { PatchCold records[]; };
// COLOR_NEIGHBORS patch indices per patch (NO_NEIGHBOR in unused slots).
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer ColorNeighbors { uint indices[]; };

// Single records, addressed by `record_address`.
// A hot record as two 16-byte words. Every record starts on 16 bytes (its buffer does, and
// records are 32 bytes), and saying so lets the driver fetch it in two 128-bit loads rather
// than eight 32-bit ones, on every intersection call.
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer HotPatchAt { uvec4 words[2]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer ColdPatchAt { PatchCold record; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer NeighborAt { uint index; };

// `base` plus `index` times `size` bytes, in 64 bits. Indexing a buffer reference's array
// (`records[index]`) lets the driver multiply the index by the record's size in 32 bits, which
// past 4 GB (134M hot records) wraps back to the buffer's start: a large set then reads other
// patches' records, and most of it vanishes.
uvec2 record_address(uvec2 base, uint index, uint size) {
    uint high;
    uint low;
    umulExtended(index, size, high, low);
    uint carry;
    uint sum = uaddCarry(base.x, low, carry);
    return uvec2(sum, base.y + high + carry);
}

PatchHot hot_record(HotPatches records, uint index) {
    HotPatchAt at = HotPatchAt(record_address(uvec2(records), index, PATCH_HOT_BYTES));
    uvec4 first = at.words[0];
    uvec4 second = at.words[1];
    return PatchHot(uintBitsToFloat(first.x), uintBitsToFloat(first.y), uintBitsToFloat(first.z),
                    uintBitsToFloat(first.w), second.x, second.y, second.z, second.w);
}

// An unpacked record (`HotRecords::Unpacked`): 64 bytes, in four 128-bit loads.
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer UnpackedPatchAt { PatchUnpacked record; };

PatchUnpacked unpacked_record(HotPatches records, uint index) {
    return UnpackedPatchAt(record_address(uvec2(records), index, PATCH_UNPACKED_BYTES)).record;
}

// The origin of patch `index`, whose hot records are unpacked where the including stage
// defines UNPACKED_RECORDS: both forms begin with it.
vec3 record_origin(HotPatches records, uint index) {
#ifdef UNPACKED_RECORDS
    return unpacked_record(records, index).origin_radius.xyz;
#else
    return patch_origin(hot_record(records, index));
#endif
}

PatchCold cold_record(ColdPatches records, uint index) {
    return ColdPatchAt(record_address(uvec2(records), index, PATCH_COLD_BYTES)).record;
}

// Slot `slot` of patch `patch_index`'s row of `width` colour neighbours.
uint color_neighbor(ColorNeighbors neighbors, uint patch_index, uint width, uint slot) {
    uvec2 row = record_address(uvec2(neighbors), patch_index, width * 4u);
    return NeighborAt(record_address(row, slot, 4u)).index;
}

// Whether a reference holds an address (objects without the buffer carry 0).
bool has_address(ColorNeighbors buffer_address) {
    return uvec2(buffer_address) != uvec2(0u);
}

#endif
