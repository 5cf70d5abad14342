// Twin of src/background.rs: the colour of a ray that hits nothing.
#ifndef POINTRAY_BACKGROUND_GLSL
#define POINTRAY_BACKGROUND_GLSL

// Gradient from `bottom` (straight down) to `top` (straight up) by 0.5 (dir.y + 1);
// a solid background is top == bottom. `direction` is unit length.
vec3 background(vec3 direction, vec3 top, vec3 bottom) {
    float s = clamp(0.5 * (direction.y + 1.0), 0.0, 1.0);
    return bottom + (top - bottom) * s;
}

#endif
