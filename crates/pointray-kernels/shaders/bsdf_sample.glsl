// Twin of src/bsdf_sample.rs: a direction drawn from a BSDF (local), its weight
// f cos / pdf (zero when the draw failed), its pdf (0 for a delta lobe).
#ifndef POINTRAY_BSDF_SAMPLE_GLSL
#define POINTRAY_BSDF_SAMPLE_GLSL

struct BsdfSample {
    vec3 direction;
    vec3 weight;
    float pdf;
    bool delta;
};

BsdfSample bsdf_sample_none() {
    return BsdfSample(vec3(0.0, 0.0, 1.0), vec3(0.0), 0.0, false);
}

#endif
