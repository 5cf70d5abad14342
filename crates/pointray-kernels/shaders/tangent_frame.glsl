// Twin of src/tangent_frame.rs: a patch's tangent frame from a normal and an angle.
#ifndef POINTRAY_PACKED_FRAME_GLSL
#define POINTRAY_PACKED_FRAME_GLSL

const float PI = 3.14159265358979;
// The largest magnitude of an snorm11 octahedral code, and of the unorm10 angle.
const int NORMAL_STEPS = 1023;
const float ANGLE_STEPS = 1023.0;

struct TangentFrame {
    vec3 t1;
    vec3 t2;
    vec3 n;
};

// Duff et al. 2017: two unit tangents of unit normal n, without a branch that loses precision.
void normal_basis(vec3 n, out vec3 b1, out vec3 b2) {
    float sign_z = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (sign_z + n.z);
    float b = n.x * n.y * a;
    b1 = vec3(1.0 + sign_z * n.x * n.x * a, sign_z * b, -sign_z * n.x);
    b2 = vec3(b, sign_z + n.y * n.y * a, -n.y);
}

// z from the integers, so that its sign is exact whatever the division's rounding.
vec3 octahedral_decode(int a, int b) {
    a = clamp(a, -NORMAL_STEPS, NORMAL_STEPS);
    b = clamp(b, -NORMAL_STEPS, NORMAL_STEPS);
    float steps = float(NORMAL_STEPS);
    float z = float(NORMAL_STEPS - abs(a) - abs(b)) / steps;
    float x = float(a) / steps;
    float y = float(b) / steps;
    float fold = max(-z, 0.0);
    x = x + (x >= 0.0 ? -fold : fold);
    y = y + (y >= 0.0 ? -fold : fold);
    return normalize(vec3(x, y, z));
}

// An snorm11 code in the low 11 bits, sign-extended by the arithmetic shift of an int.
int snorm11_code(uint bits) {
    return int(bits << 21) >> 21;
}

// The normal of a frame word's low 22 bits.
vec3 unpack_normal(uint word) {
    return octahedral_decode(snorm11_code(word), snorm11_code(word >> 11));
}

TangentFrame tangent_frame_from_normal_and_angle(vec3 n, float angle) {
    vec3 b1;
    vec3 b2;
    normal_basis(n, b1, b2);
    vec3 t1 = normalize(cos(angle) * b1 + sin(angle) * b2);
    return TangentFrame(t1, cross(n, t1), n);
}

TangentFrame unpack_frame(uint word) {
    float fraction = float(word >> 22) / ANGLE_STEPS;
    return tangent_frame_from_normal_and_angle(unpack_normal(word), fraction * PI);
}

#endif
