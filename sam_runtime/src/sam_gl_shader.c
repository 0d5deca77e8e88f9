/* Embedded shaders: include expansion with #line bookkeeping, compilation,
 * and error messages rewritten to the original file and line. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_gl.h"
#include "sam_gl_embedded.h"

size_t sam_gl_shader_file_count(void)
{
    return sam_gl_embedded_file_count;
}

const char *sam_gl_shader_file_name(size_t index)
{
    return index < sam_gl_embedded_file_count ? sam_gl_embedded_files[index].name : NULL;
}

static int find_file(const char *name, size_t len)
{
    for (size_t i = 0; i < sam_gl_embedded_file_count; ++i)
        if (strlen(sam_gl_embedded_files[i].name) == len && !strncmp(sam_gl_embedded_files[i].name, name, len))
            return (int)i;
    return -1;
}

/* Appends fmt with two ints (at most 63 characters). */
static void appendf(sam_text *t, const char *fmt, int a, int b)
{
    char buf[64];
    int n = snprintf(buf, sizeof buf, fmt, a, b);
    sam_text_append(t, buf, (size_t)n);
}

/* Source-string numbers in #line directives are file index + 1, so 0
 * stays free for text given directly. */
#define SOURCE_ID(index) ((index) + 1)

/* Appends file `index` (its #version line skipped when `skip_version`),
 * expanding includes. `included` marks files already in the program. */
static sam_status expand(int index, const char *file_name, const char *body, int skip_version, unsigned char *included,
                         int depth, sam_text *out, sam_error *err)
{
    if (depth > 16)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: includes nested more than 16 deep (a cycle?)", file_name);
    int line = 1;
    const char *p = body;
    while (*p) {
        const char *eol = strchr(p, '\n');
        size_t n = eol ? (size_t)(eol - p) : strlen(p);
        const char *s = p;
        while (s < p + n && (*s == ' ' || *s == '\t'))
            s++;
        if (skip_version && line == 1 && !strncmp(s, "#version", 8)) {
            /* dropped: the program's #version comes first */
        } else if (!strncmp(s, "#include", 8)) {
            const char *q1 = memchr(s, '"', (size_t)(p + n - s));
            const char *q2 = q1 ? memchr(q1 + 1, '"', (size_t)(p + n - q1 - 1)) : NULL;
            if (!q2)
                return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s:%d: malformed #include (expected #include \"file\")",
                                file_name, line);
            int inc = find_file(q1 + 1, (size_t)(q2 - q1 - 1));
            if (inc < 0)
                return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s:%d: #include \"%.*s\": no such embedded shader file",
                                file_name, line, (int)(q2 - q1 - 1), q1 + 1);
            if (!included[inc]) {
                included[inc] = 1;
                appendf(out, "#line 1 %d\n", SOURCE_ID(inc), 0);
                sam_status st = expand(inc, sam_gl_embedded_files[inc].name, sam_gl_embedded_files[inc].text, 1,
                                       included, depth + 1, out, err);
                if (st != SAM_OK)
                    return st;
                appendf(out, "#line %d %d\n", line + 1, index >= 0 ? SOURCE_ID(index) : 0);
            } else {
                sam_text_append(out, "\n", 1);
            }
        } else {
            sam_text_append(out, p, n);
            sam_text_append(out, "\n", 1);
        }
        ++line;
        p = eol ? eol + 1 : p + n;
    }
    return SAM_OK;
}

/* Builds the program text: #version, defines, then the file body. */
static sam_status build_source(int index, const char *name, const char *body, const char *defines, char **source,
                               sam_error *err)
{
    *source = NULL;
    if (strncmp(body, "#version", 8))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s:1: the first line must be the #version directive", name);
    unsigned char *included = calloc(sam_gl_embedded_file_count + 1, 1);
    if (!included)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory", name);
    if (index >= 0)
        included[index] = 1;
    sam_text out = {0};
    const char *eol = strchr(body, '\n');
    sam_text_append(&out, body, eol ? (size_t)(eol - body + 1) : strlen(body));
    if (defines) {
        sam_text_append(&out, defines, strlen(defines));
        sam_text_append(&out, "\n", 1);
    }
    appendf(&out, "#line 2 %d\n", index >= 0 ? SOURCE_ID(index) : 0, 0);
    sam_status st = expand(index, name, body, 1, included, 0, &out, err);
    free(included);
    if (st == SAM_OK && out.oom)
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory", name);
    if (st != SAM_OK) {
        free(out.p);
        return st;
    }
    *source = out.p;
    return SAM_OK;
}

sam_status sam_gl_shader_source(const char *name, const char *defines, char **source, sam_error *err)
{
    int index = find_file(name, strlen(name));
    if (index < 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "shader %s: no such embedded shader file", name);
    return build_source(index, name, sam_gl_embedded_files[index].text, defines, source, err);
}

/* Rewrites the first error of a GL info log to "file:line: message". Mesa
 * writes "0:12(3): error: ...", NVIDIA "0(12) : error C1008: ...". */
static void first_error(const char *log, const char *direct_name, char *out, size_t n)
{
    const char *line = log;
    while (line && *line) {
        const char *eol = strchr(line, '\n');
        int len = eol ? (int)(eol - line) : (int)strlen(line);
        int source = -1, number = -1, used = 0;
        if (sscanf(line, "%d:%d(%*d): %n", &source, &number, &used) == 2 && used > 0) {
        } else if (sscanf(line, "%d(%d) : %n", &source, &number, &used) == 2 && used > 0) {
        } else {
            source = -1;
        }
        if (source >= 0 && (strstr(line, "error") || strstr(line, "ERROR"))) {
            const char *file = source == 0 ? direct_name
                               : (size_t)source <= sam_gl_embedded_file_count
                                   ? sam_gl_embedded_files[source - 1].name
                                   : "?";
            snprintf(out, n, "%s:%d: %.*s", file, number, len - used, line + used);
            return;
        }
        line = eol ? eol + 1 : NULL;
    }
    /* No parsable line: give the log's first line. */
    const char *eol = strchr(log, '\n');
    snprintf(out, n, "%s: %.*s", direct_name, eol ? (int)(eol - log) : (int)strlen(log), log);
}

static sam_status compile(GLenum kind, const char *name, const char *source, GLuint *shader, sam_error *err)
{
    *shader = glCreateShader(kind);
    glShaderSource(*shader, 1, &source, NULL);
    glCompileShader(*shader);
    GLint ok = 0;
    glGetShaderiv(*shader, GL_COMPILE_STATUS, &ok);
    if (ok)
        return SAM_OK;
    GLint len = 0;
    glGetShaderiv(*shader, GL_INFO_LOG_LENGTH, &len);
    char *log = malloc((size_t)len + 1);
    char msg[SAM_ERROR_MESSAGE_SIZE] = "";
    if (log) {
        glGetShaderInfoLog(*shader, len, NULL, log);
        log[len] = 0;
        first_error(log, name, msg, sizeof msg);
        free(log);
    }
    glDeleteShader(*shader);
    *shader = 0;
    return sam_fail(err, SAM_ERR_FORMAT, "shader compile error: %s", msg);
}

static sam_status link(GLuint *shaders, int count, const char *name, GLuint *program, sam_error *err)
{
    *program = glCreateProgram();
    for (int i = 0; i < count; ++i)
        glAttachShader(*program, shaders[i]);
    glLinkProgram(*program);
    for (int i = 0; i < count; ++i)
        glDeleteShader(shaders[i]);
    GLint ok = 0;
    glGetProgramiv(*program, GL_LINK_STATUS, &ok);
    if (ok)
        return SAM_OK;
    char log[SAM_ERROR_MESSAGE_SIZE] = "";
    glGetProgramInfoLog(*program, sizeof log, NULL, log);
    char msg[SAM_ERROR_MESSAGE_SIZE];
    first_error(log, name, msg, sizeof msg);
    glDeleteProgram(*program);
    *program = 0;
    return sam_fail(err, SAM_ERR_FORMAT, "shader link error in %s: %s", name, msg);
}

static sam_status compile_file(GLenum kind, const char *name, const char *defines, GLuint *shader, sam_error *err)
{
    char *source;
    sam_status st = sam_gl_shader_source(name, defines, &source, err);
    if (st != SAM_OK)
        return st;
    st = compile(kind, name, source, shader, err);
    free(source);
    return st;
}

sam_status sam_gl_compute_program(const char *name, const char *defines, GLuint *program, sam_error *err)
{
    *program = 0;
    GLuint shader;
    sam_status st = compile_file(GL_COMPUTE_SHADER, name, defines, &shader, err);
    if (st != SAM_OK)
        return st;
    return link(&shader, 1, name, program, err);
}

sam_status sam_gl_render_program(const char *vertex, const char *fragment, const char *defines, GLuint *program,
                                 sam_error *err)
{
    *program = 0;
    GLuint shaders[2];
    sam_status st = compile_file(GL_VERTEX_SHADER, vertex, defines, &shaders[0], err);
    if (st != SAM_OK)
        return st;
    st = compile_file(GL_FRAGMENT_SHADER, fragment, defines, &shaders[1], err);
    if (st != SAM_OK) {
        glDeleteShader(shaders[0]);
        return st;
    }
    return link(shaders, 2, vertex, program, err);
}

sam_status sam_gl_compute_program_from_text(const char *file_name, const char *body, GLuint *program, sam_error *err)
{
    *program = 0;
    char *source;
    sam_status st = build_source(-1, file_name, body, NULL, &source, err);
    if (st != SAM_OK)
        return st;
    GLuint shader;
    st = compile(GL_COMPUTE_SHADER, file_name, source, &shader, err);
    free(source);
    if (st != SAM_OK)
        return st;
    return link(&shader, 1, file_name, program, err);
}
