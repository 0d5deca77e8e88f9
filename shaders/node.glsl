// A cut map's tree node as the node pass writes it (nodes.comp) and the
// rest-K and translucency passes read it. L_d and its split come first:
// the rest pass reads only those, and together they fill one 32-byte
// sector, where a layout with the geometry between them cost a GPU two
// sectors for every node sample.
struct Node {
    vec4 ld;            // area-weighted mean L_d
    vec4 ld_diff;       // L_d(child 1) - L_d(child 0): a sample moves along it by its tau
    vec4 centroid_area; // centroid (model units), area (mm^2)
    vec4 normal;        // area-weighted mean normal (not unit)
};
