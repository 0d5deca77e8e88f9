/* The node pass of a cut map (samfile.h, version 2): each tree node's area
 * and its area-weighted centroid, mean normal and L_d, summed from the
 * vertices up so that every child is ready before its parent (state in
 * rt->nodes). A flat map has no nodes and the pass does nothing.
 * Not installed. */
#ifndef SAM_RUNTIME_NODES_H
#define SAM_RUNTIME_NODES_H

#include "sam_runtime_internal.h"

/* Part of sam_runtime_create, after the mesh's buffers: uploads the tree
 * (children, and every vertex's and node's parent for the walk), keeps the
 * level offsets and compiles the program. Errors: SAM_ERR_OUT_OF_MEMORY,
 * SAM_ERR_UNSUPPORTED (buffer limits), SAM_ERR_FORMAT (shader errors). */
sam_status sam_runtime_nodes_create(sam_runtime *rt, const samfile_data *sam, sam_error *err);
void sam_runtime_nodes_destroy(sam_runtime *rt);

/* Records the pass for the current positions, normals and L_d, one
 * dispatch from the vertices up (nodes.comp); at rest, after one full pass
 * there, L_d alone. Leaves SAM_B_NODE_ARRIVALS bound to its own buffer. The
 * translucency pass calls it first. */
void sam_runtime_nodes_update(sam_runtime *rt);

/* While the buffers hold the rest pose: the nodes' rest centroids and
 * areas, kept for the posed K (sam_runtime_deform_keep_rest calls it once).
 * Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_nodes_keep_rest(sam_runtime *rt, sam_error *err);

#endif
