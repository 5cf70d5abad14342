// Twin of src/random_sequence.rs: a per-pixel stream of uniform numbers, hashed from
// (seed, pixel, sample, dimension) in integer arithmetic so that CPU and GPU agree bit for bit.
#ifndef POINTRAY_RANDOM_SEQUENCE_GLSL
#define POINTRAY_RANDOM_SEQUENCE_GLSL

// PCG-RXS-M-XS of one LCG step (Jarzynski and Olano 2020).
uint pcg_hash(uint value) {
    uint state = value * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

struct RandomSequence {
    uint key;
    uint dimension;
};

RandomSequence random_sequence(uint seed, uvec2 pixel, uint sample_index) {
    uint key = pcg_hash(seed + pcg_hash(pixel.x + pcg_hash(pixel.y + pcg_hash(sample_index))));
    return RandomSequence(key, 0u);
}

// Uniform in [0, 1): the hash's top 24 bits, exactly representable. Two rounds: one leaves
// the dimensions of a sample correlated enough to bias rare joint events.
float random_next(inout RandomSequence sequence) {
    uint bits = pcg_hash(pcg_hash(sequence.key ^ pcg_hash(sequence.dimension)));
    sequence.dimension += 1u;
    return float(bits >> 8u) * (1.0 / 16777216.0);
}

vec2 random_next2(inout RandomSequence sequence) {
    float x = random_next(sequence);
    float y = random_next(sequence);
    return vec2(x, y);
}

#endif
