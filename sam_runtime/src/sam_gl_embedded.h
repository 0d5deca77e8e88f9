/* Internal: the shader files compiled into the library (generated). */
#ifndef SAM_GL_EMBEDDED_H
#define SAM_GL_EMBEDDED_H

#include <stddef.h>

typedef struct sam_gl_embedded_file {
    const char *name;
    const char *text;
} sam_gl_embedded_file;

extern const sam_gl_embedded_file sam_gl_embedded_files[];
extern const size_t sam_gl_embedded_file_count;

#endif
