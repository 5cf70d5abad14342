// The per-patch buffers, read by device address: the records of layout.glsl and the colour
// neighbour lists (src/interpolate_color.rs). Shared by bindings.glsl and the kernels that
// walk a patch set, which compile outside the ray-tracing stages too.
#ifndef POINTRAY_PATCH_BUFFERS_GLSL
#define POINTRAY_PATCH_BUFFERS_GLSL

#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require

#include "layout.glsl"

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer HotPatches { PatchHot records[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer ColdPatches { PatchCold records[]; };
// COLOR_NEIGHBORS patch indices per patch (NO_NEIGHBOR in unused slots).
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer ColorNeighbors { uint indices[]; };

// Whether a reference holds an address (objects without the buffer carry 0).
bool has_address(ColorNeighbors buffer_address) {
    return uvec2(buffer_address) != uvec2(0u);
}

#endif
