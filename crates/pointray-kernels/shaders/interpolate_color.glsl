// Twin of src/interpolate_color.rs: the colour at a hit, blended with a Wendland weight of
// each point's own reach over the point nearest the hit and its neighbours, so that every
// patch hit at one point gives it the same colour (no blocky seams).
#ifndef POINTRAY_INTERPOLATE_COLOR_GLSL
#define POINTRAY_INTERPOLATE_COLOR_GLSL

#include "patch_buffers.glsl"

const uint COLOR_NEIGHBORS = 12u;
const uint NO_NEIGHBOR = 0xffffffffu;
const uint COLOR_WALK_SCANS = 3u;

// theta(r) = (1 - r)^4 (4r + 1) of r = distance / reach, 0 from r = 1 on.
float color_weight(float distance_to_point, float reach) {
    if (reach <= 0.0 || distance_to_point >= reach) {
        return 0.0;
    }
    float r = distance_to_point / reach;
    float one_minus = 1.0 - r;
    float squared = one_minus * one_minus;
    return squared * squared * (4.0 * r + 1.0);
}

vec3 color_from_rgba8(uint rgba8) {
    return vec3(rgba8 & 0xffu, (rgba8 >> 8) & 0xffu, (rgba8 >> 16) & 0xffu) / 255.0;
}

// Rounds half up, written out as the Rust twin does (GLSL's round() may round half to even).
uint color_to_rgba8(vec3 color) {
    uvec3 bytes = uvec3(floor(clamp(color, 0.0, 1.0) * 255.0 + 0.5));
    return bytes.r | (bytes.g << 8) | (bytes.b << 16) | (255u << 24);
}

// One pass over a point and its neighbours: their weighted colours, and which of them lies
// nearest the hit.
struct ColorScan {
    vec3 weighted_color;
    float total_weight;
    uint nearest;
};

ColorScan color_scan_around(vec3 position, uint centre, HotPatches hot, ColdPatches cold, ColorNeighbors neighbors) {
    ColorScan scan = ColorScan(vec3(0.0), 0.0, centre);
    float nearest_distance = 1.0 / 0.0;
    uint slots = has_address(neighbors) ? COLOR_NEIGHBORS : 0u;
    for (uint slot = 0u; slot <= slots; ++slot) {
        uint j = slot == 0u ? centre : color_neighbor(neighbors, centre, COLOR_NEIGHBORS, slot - 1u);
        if (j == NO_NEIGHBOR) {
            continue;
        }
        float distance_to_point = distance(position, record_origin(hot, j));
        PatchCold record = cold_record(cold, j);
        float weight = color_weight(distance_to_point, record.color_reach);
        scan.weighted_color += weight * color_from_rgba8(record.color_rgba8);
        scan.total_weight += weight;
        if (distance_to_point < nearest_distance) {
            scan.nearest = j;
            nearest_distance = distance_to_point;
        }
    }
    return scan;
}

// The colour at `position` (the patches' space) on patch `hit`, as linear RGBA8; where no
// point reaches it, the colour of the point nearest it. `neighbors` may be 0: then the blend
// is over the hit patch alone. Indices are trusted (the loader checks them).
uint interpolate_color(vec3 position, uint hit, HotPatches hot, ColdPatches cold, ColorNeighbors neighbors) {
    uint centre = hit;
    ColorScan scan;
    for (uint step = 0u; step < COLOR_WALK_SCANS; ++step) {
        scan = color_scan_around(position, centre, hot, cold, neighbors);
        if (scan.nearest == centre) {
            break;
        }
        centre = scan.nearest;
    }
    if (scan.total_weight <= 0.0) {
        return cold_record(cold, scan.nearest).color_rgba8;
    }
    return color_to_rgba8(scan.weighted_color / scan.total_weight);
}

#endif
