// Twin of src/face_forward.rs: turning a normal toward the viewer.
#ifndef POINTRAY_FACE_FORWARD_GLSL
#define POINTRAY_FACE_FORWARD_GLSL

// `normal`, flipped if it points along `ray_direction` (away from the ray's origin).
vec3 face_forward(vec3 normal, vec3 ray_direction) {
    return dot(normal, ray_direction) > 0.0 ? -normal : normal;
}

#endif
