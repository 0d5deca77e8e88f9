// A stored sample: its back-side vertex, or vertex_count + tree node, or
// 0xFFFFFFFF for none (the rest of the vertex's slots are none too); and
// K' (eq. 15), or in the rest-K buffer K itself, packed into two words
// next to its index. A per-sample buffer is a uint array of three words per
// sample (SAMPLE_LOAD, SAMPLE_STORE): one 12-byte read, not the 16 bytes of
// four floats.
//
// Each channel of K packs into 21 bits: float's exponent and the top 13
// bits of its mantissa, rounded (sam_runtime_pack_k packs the same way on
// the CPU), so it comes back within 2^-14 of itself whatever the other
// channels hold. Four floats made the cut map's passes on a GPU pay for
// bytes (27.8 samples read per vertex against the flat map's 3), and put a
// mesh of about 260k vertices at N = 32 past the 128 MiB storage block
// that llvmpipe and the GL minimum allow. A shared exponent, tried first,
// lost whole channels: a node's K' can differ between channels by 10^10
// (its centroid far out in the faster channel's tail).
//
// Every per-sample buffer (samples, rest K, tau) is slot-major: slot k of
// vertex v is sample k * vertex_count + v. The invocations of a warp,
// neighbouring vertices, then read one slot together as one contiguous run;
// the vertex-major rows of the .sam put each of those reads in a sector of
// its own, and a GPU paid about 4x for the cut map's rest pass.
struct Sample {
    uint index;
    uvec2 k; // see sample_k
};

#define SAMPLE_LOAD(buf, i) Sample(buf[3u * (i)], uvec2(buf[3u * (i) + 1u], buf[3u * (i) + 2u]))
#define SAMPLE_STORE(buf, i, s) \
    { Sample s_ = (s); buf[3u * (i)] = s_.index; buf[3u * (i) + 1u] = s_.k.x; buf[3u * (i) + 2u] = s_.k.y; }

// Which sample of a per-sample buffer of vertex_count rows is slot k of vertex v.
uint sample_slot(uint v, uint k, uint vertex_count)
{
    return k * vertex_count + v;
}

vec3 sample_k(Sample s)
{
    uvec3 c = uvec3(s.k.x, s.k.x >> 21 | s.k.y << 11, s.k.y >> 10) & 0x1FFFFFu;
    return uintBitsToFloat(c << 10);
}

// Channels below 0 pack as 0; above 1e38 as 1e38, where rounding
// cannot carry into infinity.
Sample make_sample(uint index, vec3 k)
{
    uvec3 c = (floatBitsToUint(min(max(k, vec3(0.0)), vec3(1.0e38))) + 0x200u) >> 10;
    return Sample(index, uvec2(c.r | c.g << 21, c.g >> 11 | c.b << 10));
}
