// Twin of src/quadratic_roots.rs: real roots of a t^2 + b t + c = 0, robustly.
#ifndef POINTRAY_QUADRATIC_ROOTS_GLSL
#define POINTRAY_QUADRATIC_ROOTS_GLSL

// Below this |a| / |b| the equation is solved as linear (the dropped root is beyond 1e6).
const float LINEAR_THRESHOLD = 1e-6;

// Returns how many roots (0, 1 or 2); `roots` holds them ascending (a single root twice).
// Degenerate equations (a = b = 0) report none.
uint quadratic_roots(float a, float b, float c, out vec2 roots) {
    roots = vec2(0.0);
    if (abs(a) <= LINEAR_THRESHOLD * abs(b)) {
        if (b == 0.0) {
            return 0u;
        }
        float t = -c / b;
        roots = vec2(t);
        return 1u;
    }
    float discriminant = b * b - 4.0 * a * c;
    if (discriminant < 0.0) {
        return 0u;
    }
    // sign(b) with sign(0) = +1, spelled out because GLSL's sign(0) is 0.
    float sign_b = b >= 0.0 ? 1.0 : -1.0;
    float q = -0.5 * (b + sign_b * sqrt(discriminant));
    float first = q / a;
    // q = 0 only when b = 0 and disc = 0, which forces c = 0: a double root at 0.
    float second = q != 0.0 ? c / q : first;
    roots = vec2(min(first, second), max(first, second));
    return 2u;
}

#endif
