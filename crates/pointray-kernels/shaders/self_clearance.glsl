// Twin of src/self_clearance.rs: the t_min of secondary rays leaving a patch, so that a
// surface does not shadow itself on its overlapping neighbours.
#ifndef POINTRAY_SELF_CLEARANCE_GLSL
#define POINTRAY_SELF_CLEARANCE_GLSL

const float SELF_CLEARANCE_FRACTION = 1.0;

float self_clearance(float radius) {
    return SELF_CLEARANCE_FRACTION * radius;
}

// The path integrator's rays start off the surface along its normal by this share of the
// clearance and skip nothing, so that none passes through a wall closer than the clearance.
const float PATH_OFFSET_SHARE = 0.05;

float path_ray_offset(float clearance, float epsilon) {
    return max(PATH_OFFSET_SHARE * clearance, epsilon);
}

#endif
