// Twin of src/self_clearance.rs: the t_min of secondary rays leaving a patch, so that a
// surface does not shadow itself on its overlapping neighbours.
#ifndef POINTRAY_SELF_CLEARANCE_GLSL
#define POINTRAY_SELF_CLEARANCE_GLSL

const float SELF_CLEARANCE_FRACTION = 1.0;

float self_clearance(float radius) {
    return SELF_CLEARANCE_FRACTION * radius;
}

#endif
