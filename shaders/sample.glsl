// A stored sample: its back-side vertex, or vertex_count + tree node, or
// 0xFFFFFFFF for none (the rest of the vertex's slots are none too); and
// K' (eq. 15), or in the rest-K buffer K itself, next to its index: one
// 16-byte read.
//
// Every per-sample buffer (samples, rest K, tau) is slot-major: slot k of
// vertex v is element k * vertex_count + v. The invocations of a warp,
// neighbouring vertices, then read one slot together as one contiguous run;
// the vertex-major rows of the .sam put each of those 16-byte reads in a
// sector of its own, and a GPU paid about 4x for the cut map's rest pass.
struct Sample {
    uint index;
    float kr, kg, kb;
};

// Where slot k of vertex v lies in a per-sample buffer of vertex_count rows.
uint sample_slot(uint v, uint k, uint vertex_count)
{
    return k * vertex_count + v;
}
