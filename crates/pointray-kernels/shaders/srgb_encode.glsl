// Twin of src/srgb_encode.rs: linear colour to display bytes.
#ifndef POINTRAY_SRGB_ENCODE_GLSL
#define POINTRAY_SRGB_ENCODE_GLSL

// The sRGB transfer function (IEC 61966-2-1) to 8 bits, after clamping to [0, 1]. NaN
// becomes 0 (GLSL's clamp leaves NaN undefined, hence the explicit test).
uint srgb_encode(float linear) {
    linear = isnan(linear) ? 0.0 : clamp(linear, 0.0, 1.0);
    float encoded = linear <= 0.0031308 ? 12.92 * linear : 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
    return uint(round(encoded * 255.0));
}

// One opaque sRGB8 RGBA pixel, red in the low byte.
uint srgb_encode_rgba8(vec3 linear) {
    return srgb_encode(linear.r) | (srgb_encode(linear.g) << 8) | (srgb_encode(linear.b) << 16) | (0xffu << 24);
}

// The same pixel with blue in the low byte, for B8G8R8A8 swapchain images.
uint srgb_encode_bgra8(vec3 linear) {
    return srgb_encode_rgba8(linear.bgr);
}

#endif
