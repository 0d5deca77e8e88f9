/*
 * Structural validation of mesh files before OpenMesh parses them.
 *
 * OpenMesh's readers trust what they parse: a PLY header without end_header
 * makes its parser loop forever, a property before any element crashes it,
 * and element, face or list counts larger than the file make it allocate
 * gigabytes while reading past the end (all found by fuzz/fuzz_mesh). So
 * every PLY (header grammar, then each element instance of the body, ASCII
 * or binary), ASCII OFF (keyword, counts, vertex and face lines), OBJ
 * (numbers and face corners; Debian builds OpenMesh with assertions, which
 * abort on a bad normal index) and binary STL (size) is walked here first,
 * and only a file whose every count and index fits reaches OpenMesh.
 *
 * Every number must also fit the 32-bit float it will be stored in:
 * OpenMesh's stream extraction fails on "1e39" and its OBJ reader then
 * drops the whole vertex line, so every later face index would point at
 * the wrong vertex. The counts found here (sam_mesh_expect) are checked
 * against what the reader delivered (sam_mesh.c), so any other
 * disagreement between this walk and OpenMesh fails the load too.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam_mesh_ply.h"
#include "sam_mesh_soup.h"
#include "sam_mesh_text.h"

/* ---- PLY */

/* OpenMesh's reader takes a list count typed by these names only. */
static int count_name_read(const char *tok, int len)
{
    return sam_mesh_token_is(tok, len, "uchar") || sam_mesh_token_is(tok, len, "uint8") || sam_mesh_token_is(tok, len, "uint16") ||
           sam_mesh_token_is(tok, len, "int");
}

/* Reads a list count of `size` bytes at `p`; -1 when negative. */
static long long read_count(const unsigned char *p, int size, int is_signed, int big_endian)
{
    unsigned long long v = 0;
    for (int i = 0; i < size; ++i)
        v |= (unsigned long long)p[big_endian ? size - 1 - i : i] << (8 * i);
    if (is_signed && (v >> (8 * size - 1)) & 1)
        return -1;
    return (long long)v;
}

static int is_signed(sam_mesh_ply_type t)
{
    return t == SAM_MESH_PLY_INT8 || t == SAM_MESH_PLY_INT16 || t == SAM_MESH_PLY_INT32;
}

static sam_status ply_body_binary(const char *path, const sam_mesh_ply_element *el, int elements,
                                  const unsigned char *body,
                                  size_t size, int big_endian, sam_error *err)
{
    size_t off = 0;
    for (int e = 0; e < elements; ++e) {
        for (unsigned long long i = 0; i < el[e].count; ++i) {
            for (int k = 0; k < el[e].property_count; ++k) {
                const sam_mesh_ply_property *pr = &el[e].property[k];
                const int count_size = sam_mesh_ply_type_size(pr->count_type);
                const int value_size = sam_mesh_ply_type_size(pr->value_type);
                unsigned long long need = (unsigned long long)(pr->is_list ? count_size : value_size);
                if (need > size - off)
                    goto truncated;
                if (pr->is_list) {
                    long long n = read_count(body + off, count_size, is_signed(pr->count_type), big_endian);
                    off += (size_t)count_size;
                    if (n < 0)
                        return sam_fail(err, SAM_ERR_FORMAT, "%s: PLY %s %llu has a negative list count", path,
                                        el[e].name, i);
                    need = (unsigned long long)n * (unsigned long long)value_size;
                    if (need > size - off)
                        goto truncated;
                }
                off += (size_t)need;
                continue;
            truncated:
                return sam_fail(err, SAM_ERR_FORMAT,
                                "%s: PLY body is truncated in %s %llu of %llu (offset %zu of %zu body bytes)", path,
                                el[e].name, i, el[e].count, off, size);
            }
        }
    }
    return SAM_OK;
}

/* ASCII bodies are read as a stream of tokens, as OpenMesh does. */
static sam_status ply_body_ascii(const char *path, const sam_mesh_ply_element *el, int elements, const char *body,
                                 size_t size, sam_error *err)
{
    sam_mesh_token_stream ts = {body, body + size};
    const char *tok;
    int len;
    for (int e = 0; e < elements; ++e) {
        for (unsigned long long i = 0; i < el[e].count; ++i) {
            for (int k = 0; k < el[e].property_count; ++k) {
                unsigned long long n = 1;
                if (el[e].property[k].is_list) {
                    if (!sam_mesh_next_token(&ts, &tok, &len))
                        goto truncated;
                    if (sam_mesh_token_count(tok, len, &n) != 1)
                        return sam_fail(err, SAM_ERR_FORMAT, "%s: PLY %s %llu: list count \"%.*s\" is not a count",
                                        path, el[e].name, i, len < 40 ? len : 40, tok);
                    /* Each entry takes at least two bytes (a digit and a blank). */
                    if (n > (unsigned long long)(ts.end - ts.p) / 2 + 1)
                        goto truncated;
                }
                for (unsigned long long j = 0; j < n; ++j) {
                    if (!sam_mesh_next_token(&ts, &tok, &len))
                        goto truncated;
                    const int kind = sam_mesh_token_number(tok, len);
                    if (kind != 1)
                        return sam_fail(err, SAM_ERR_FORMAT, "%s: PLY %s %llu: \"%.*s\" %s", path, el[e].name, i,
                                        len < 40 ? len : 40, tok, kind ? SAM_MESH_NOT_A_FLOAT : "is not a number");
                }
            }
            continue;
        truncated:
            return sam_fail(err, SAM_ERR_FORMAT, "%s: PLY body is truncated in %s %llu of %llu", path, el[e].name,
                            i, el[e].count);
        }
    }
    return SAM_OK;
}

/* Where OpenMesh's header parse stops after the line [line, eol): past its
 * last word, or at the start of the next line (`next`) where it reads the
 * rest of the line as a comment: after the word comment opening a line, or
 * anywhere in an obj_info line, which it reads word by word. */
static const char *reader_stop_after(const char *line, const char *eol, const char *next)
{
    sam_mesh_token_stream words = {line, eol};
    const char *word, *stop = line;
    int n, first = 1, obj_info = 0;
    while (sam_mesh_next_token(&words, &word, &n)) {
        if (sam_mesh_token_is(word, n, "comment") && (first || obj_info))
            return next;
        obj_info |= first && sam_mesh_token_is(word, n, "obj_info");
        first = 0;
        stop = word + n;
    }
    return stop;
}

/* Hands a file written again (`out`, by a writer that returned `st`) to
 * `expect` for the reader, or frees it on failure. */
static sam_status keep_rewrite(const char *path, size_t size, sam_status st, sam_text *out, const char *extension,
                               sam_mesh_expect *expect, sam_error *err)
{
    if (st == SAM_OK && out->oom)
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory writing the file again (%zu bytes)", path, size);
    if (st != SAM_OK) {
        free(out->p);
        return st;
    }
    expect->rewritten = out->p;
    expect->rewritten_size = out->len;
    expect->rewritten_extension = extension;
    return SAM_OK;
}

/* A PLY that OpenMesh would misread, written again as it reads one right
 * (sam_mesh_ply.h) into expect->rewritten. */
static sam_status rewrite_ply(const char *path, const char *data, size_t size, const sam_mesh_ply_header *h,
                              sam_mesh_expect *expect, sam_error *err)
{
    sam_text out = {0};
    sam_status st = sam_mesh_ply_rewrite(path, data, size, h, &out, &expect->corner_uvs, &expect->corner_uv_count, err);
    return keep_rewrite(path, size, st, &out, ".ply", expect, err);
}

static sam_status preflight_ply(const char *path, const char *data, size_t size, sam_mesh_expect *expect,
                                sam_error *err)
{
    sam_mesh_text_cursor c = {data, data + size, 0, data};
    const char *line, *eol;
    sam_mesh_ply_header *h = calloc(1, sizeof *h);
    if (!h)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    sam_mesh_ply_element *el = h->element;
    int elements = 0, format = -1; /* 0 ascii, 1 little, 2 big endian */
    sam_status st = SAM_OK;
    /* OpenMesh's binary reader finds the body 12 bytes (14 after a CR)
     * past where its header parse stopped: the end of the last word before
     * end_header, or the start of the line after a comment. */
    const char *reader_stop = data;
    while (sam_mesh_text_next_line(&c, &line, &eol)) {
        const char *tok[6];
        int len[6];
        int count = sam_mesh_text_tokenize(line, eol, tok, len, 6);
        int s = sam_mesh_text_shown(line, eol);
        const int ends_header = count == 1 && sam_mesh_token_is(tok[0], len[0], "end_header");
        if (count > 0 && !ends_header)
            reader_stop = reader_stop_after(line, eol, c.p);
        if (c.line_no == 1) {
            if (count != 1 || !sam_mesh_token_is(tok[0], len[0], "ply")) {
                st = sam_fail(err, SAM_ERR_FORMAT, "%s: not a PLY file (first line \"%.*s\", expected \"ply\")", path,
                              s, line);
                goto done;
            }
        } else if (c.line_no == 2) {
            static const char *const formats[] = {"ascii", "binary_little_endian", "binary_big_endian"};
            for (int f = 0; f < 3 && count == 3; ++f)
                if (sam_mesh_token_is(tok[1], len[1], formats[f]))
                    format = f;
            if (count != 3 || !sam_mesh_token_is(tok[0], len[0], "format") || format < 0 || !sam_mesh_token_is(tok[2], len[2], "1.0")) {
                st = sam_fail(err, SAM_ERR_FORMAT,
                              "%s: PLY header line 2 is \"%.*s\", expected \"format "
                              "ascii|binary_little_endian|binary_big_endian 1.0\"",
                              path, s, line);
                goto done;
            }
        } else if (count == 0 || sam_mesh_token_is(tok[0], len[0], "comment")) {
            continue;
        } else if (sam_mesh_token_is(tok[0], len[0], "obj_info")) {
            /* OpenMesh reads the header word by word and skips only the
             * words it does not know, so a keyword inside an obj_info line
             * would start an element or property there (its count taken
             * from the next line; a word that is no count sent the parser
             * into an endless loop). */
            static const char *const keywords[] = {"element", "property", "end_header"};
            sam_mesh_token_stream words = {line, eol};
            const char *word;
            int n;
            while (sam_mesh_next_token(&words, &word, &n))
                for (size_t k = 0; k < sizeof keywords / sizeof *keywords; ++k)
                    if (sam_mesh_token_is(word, n, keywords[k])) {
                        st = sam_fail(err, SAM_ERR_UNSUPPORTED,
                                      "%s: PLY header line %d: obj_info holds the keyword \"%s\", which the PLY reader "
                                      "would take for a header entry: \"%.*s\"",
                                      path, c.line_no, keywords[k], s, line);
                        goto done;
                    }
            continue;
        } else if (ends_header) {
            if (!elements) {
                st = sam_fail(err, SAM_ERR_FORMAT, "%s: PLY header declares no elements", path);
                goto done;
            }
            size_t body = (size_t)(c.p - data);
            /* The header is text in every PLY; the body only in ASCII ones. */
            if ((st = sam_mesh_check_text(path, "PLY", data, format == 0 ? size : (size_t)(c.p - data), err)) != SAM_OK)
                goto done;
            st = format == 0 ? ply_body_ascii(path, el, elements, data + body, size - body, err)
                             : ply_body_binary(path, el, elements, (const unsigned char *)data + body, size - body,
                                               format == 2, err);
            /* OpenMesh reads the elements named vertex and face; of a face,
             * the corners only from a first property that is the list
             * vertex_indices (or vertex_index): another name gave no faces,
             * a property before it garbled them. */
            int face_at = -1;
            for (int e = 0; st == SAM_OK && e < elements; ++e) {
                const sam_mesh_ply_property *first = el[e].property;
                if (!strcmp(el[e].name, "vertex")) {
                    expect->vertices = el[e].count;
                    /* After a face element, even one of 0 faces, OpenMesh
                     * read no vertices (found by fuzz_mesh_counts). */
                    if (face_at >= 0)
                        st = sam_fail(err, SAM_ERR_UNSUPPORTED,
                                      "%s: PLY element vertex (element %d) comes after element face (element %d); "
                                      "the PLY reader needs the vertices first",
                                      path, e + 1, face_at + 1);
                } else if (!strcmp(el[e].name, "face")) {
                    face_at = e;
                    expect->faces = expect->file_faces = el[e].count;
                    if (el[e].count && (!el[e].property_count || !first->is_list ||
                                        (strcmp(first->name, "vertex_indices") && strcmp(first->name, "vertex_index"))))
                        st = sam_fail(err, SAM_ERR_UNSUPPORTED,
                                      "%s: PLY face element: its first property must be the list vertex_indices (or "
                                      "vertex_index), found %s%s",
                                      path, !el[e].property_count ? "none" : first->is_list ? "the list " : "the scalar ",
                                      el[e].property_count ? first->name : "");
                }
            }
            if (st == SAM_OK) {
                h->format = format;
                h->body = body;
                h->element_count = elements;
                const size_t stop = (size_t)(reader_stop - data);
                h->reader_body = stop + (stop + 1 < size && data[stop] == '\r' && data[stop + 1] == '\n' ? 14 : 12);
                if (sam_mesh_ply_misread(h))
                    st = rewrite_ply(path, data, size, h, expect, err);
            }
            if (st == SAM_OK)
                st = sam_mesh_ply_colors(path, data, size, h, &expect->vertex_colors, err);
            if (st == SAM_OK)
                st = sam_mesh_ply_texnumbers(path, data, size, h, &expect->face_materials, err);
            expect->known = st == SAM_OK;
            goto done;
        } else if (count == 3 && sam_mesh_token_is(tok[0], len[0], "element")) {
            if (elements == SAM_MESH_PLY_MAX_ELEMENTS) {
                st = sam_fail(err, SAM_ERR_UNSUPPORTED, "%s: PLY header line %d: more than %d elements", path,
                              c.line_no, SAM_MESH_PLY_MAX_ELEMENTS);
                goto done;
            }
            sam_mesh_ply_element *e = &el[elements++];
            snprintf(e->name, sizeof e->name, "%.*s", len[1], tok[1]);
            /* OpenMesh reads every element of a name: a second vertex
             * element would add to the first. */
            for (int k = 0; k + 1 < elements; ++k)
                if (!strcmp(el[k].name, e->name)) {
                    st = sam_fail(err, SAM_ERR_FORMAT, "%s: PLY header line %d declares a second element \"%.31s\"",
                                  path, c.line_no, e->name);
                    goto done;
                }
            const int counted = sam_mesh_token_count(tok[2], len[2], &e->count);
            if (counted != 1) {
                st = counted ? sam_fail(err, SAM_ERR_FORMAT,
                                        "%s: PLY header line %d: the element count in \"%.*s\" is too large "
                                        "(above 2^64 - 1)",
                                        path, c.line_no, s, line)
                             : sam_fail(err, SAM_ERR_FORMAT, "%s: PLY header line %d: \"%.*s\" has no element count",
                                        path, c.line_no, s, line);
                goto done;
            }
            if (e->count > size) {
                st = sam_fail(err, SAM_ERR_FORMAT,
                              "%s: PLY header line %d declares %llu elements (\"%.*s\") but the file has only %zu "
                              "bytes",
                              path, c.line_no, e->count, s, line, size);
                goto done;
            }
        } else if (sam_mesh_token_is(tok[0], len[0], "property") && elements &&
                   el[elements - 1].property_count < SAM_MESH_PLY_MAX_PROPERTIES &&
                   ((count == 3 && sam_mesh_ply_type_of(tok[1], len[1])) ||
                    (count == 5 && sam_mesh_token_is(tok[1], len[1], "list") && sam_mesh_ply_type_of(tok[2], len[2]) &&
                     sam_mesh_ply_type_of(tok[3], len[3])))) {
            sam_mesh_ply_property *pr = &el[elements - 1].property[el[elements - 1].property_count++];
            pr->is_list = count == 5;
            snprintf(pr->name, sizeof pr->name, "%.*s", len[count - 1], tok[count - 1]);
            if (pr->is_list) {
                pr->count_type = sam_mesh_ply_type_of(tok[2], len[2]);
                pr->count_name_read = count_name_read(tok[2], len[2]);
                pr->value_type = sam_mesh_ply_type_of(tok[3], len[3]);
                if (pr->count_type == SAM_MESH_PLY_FLOAT32 || pr->count_type == SAM_MESH_PLY_FLOAT64) {
                    st = sam_fail(err, SAM_ERR_FORMAT,
                                  "%s: PLY header line %d: a list's count must have an integer type: \"%.*s\"", path,
                                  c.line_no, s, line);
                    goto done;
                }
            } else {
                pr->value_type = sam_mesh_ply_type_of(tok[1], len[1]);
            }
        } else {
            st = sam_fail(err, SAM_ERR_FORMAT, "%s: PLY header line %d is not valid: \"%.*s\"", path, c.line_no, s,
                          line);
            goto done;
        }
    }
    st = sam_fail(err, SAM_ERR_FORMAT, "%s: PLY header has no end_header line", path);
done:
    free(h);
    return st;
}

/* ---- OFF (ASCII) */

/* OpenMesh's OFF reader takes the first line for the keyword alone, the
 * next for exactly three counts, and every later value by stream
 * extraction: a '#' comment, counts on the keyword's line (ModelNet's
 * "OFF490 518 0" too), a missing edge count or a face colour would shift
 * every number after it. Files in the wild have all of them (Geomview's
 * comments, MeshLab's face colours), so such a file is written again as
 * OpenMesh reads it (sam_mesh_expect.rewritten) rather than refused. */

/* Next line with a token, cut at a '#' (the rest of the line is a
 * comment, *commented set); its token count (storing at most `max`), -1 at
 * the end of the file. *eol is where its content ends. */
static int next_content_line(sam_mesh_text_cursor *c, const char **line, const char **eol, const char **tok, int *len, int max,
                             int *commented)
{
    while (sam_mesh_text_next_line(c, line, eol)) {
        const char *hash = memchr(*line, '#', (size_t)(*eol - *line));
        if (hash)
            *eol = hash, *commented = 1;
        int count = sam_mesh_text_tokenize(*line, *eol, tok, len, max);
        if (count > 0)
            return count;
    }
    return -1;
}

#define OFF_MAX_TOKENS 16

/* Walks an OFF file, checking every line's layout exactly; with `out`,
 * writes it again as OpenMesh reads it. *rewrite (may be NULL) is set
 * when the file needs that. */
static sam_status walk_off(const char *path, const char *data, size_t size, sam_mesh_expect *expect, sam_text *out,
                           int *rewrite, sam_error *err)
{
    sam_mesh_text_cursor c = {data, data + size, 0, data};
    const char *line = data, *eol = data;
    const char *tok[OFF_MAX_TOKENS];
    int len[OFF_MAX_TOKENS], commented = 0, reshaped = 0;
    int count = next_content_line(&c, &line, &eol, tok, len, OFF_MAX_TOKENS, &commented);
    if (count < 0)
        return sam_fail(err, SAM_ERR_FORMAT, "%s: OFF file has no header", path);
    /* [ST][C][N]OFF: texture coordinates, colours, normals per vertex. */
    const char *kw = tok[0];
    int kw_len = len[0], st_uv = 0, colour = 0, normal = 0, i = 0;
    if (kw_len >= 2 && kw[0] == 'S' && kw[1] == 'T')
        st_uv = 1, i = 2;
    if (i < kw_len && kw[i] == 'C')
        colour = 1, i++;
    if (i < kw_len && kw[i] == 'N')
        normal = 1, i++;
    if (kw_len - i < 3 || strncmp(kw + i, "OFF", 3) ||
        (kw_len - i > 3 && sam_mesh_token_count(kw + i + 3, kw_len - i - 3, &(unsigned long long){0}) == 0))
        return sam_fail(err, SAM_ERR_FORMAT,
                        "%s: not an OFF file (first line \"%.*s\"; expected OFF, COFF, NOFF, STOFF or a combination)",
                        path, sam_mesh_text_shown(line, c.eol), line);
    if (count == 2 && sam_mesh_token_is(tok[1], len[1], "BINARY"))
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "%s: binary OFF is not supported; use ASCII OFF or PLY", path);
    /* The counts: on the keyword's line after it (the first may be glued
     * to it), or alone on the next. */
    const char *count_tok[4];
    int count_len[4], counts = 0;
    if (kw_len - i > 3)
        count_tok[counts] = kw + i + 3, count_len[counts++] = kw_len - i - 3;
    for (int k = 1; k < count && k < OFF_MAX_TOKENS && counts < 4; ++k)
        count_tok[counts] = tok[k], count_len[counts++] = len[k];
    if (counts)
        reshaped = 1;
    else {
        count = next_content_line(&c, &line, &eol, tok, len, OFF_MAX_TOKENS, &commented);
        for (int k = 0; k < count && k < OFF_MAX_TOKENS && counts < 4; ++k)
            count_tok[counts] = tok[k], count_len[counts++] = len[k];
    }
    unsigned long long value[3] = {0, 0, 0};
    int numbers = counts == 2 || counts == 3 ? counts : -1;
    for (int k = 0; k < numbers; ++k)
        if (sam_mesh_token_count(count_tok[k], count_len[k], &value[k]) != 1)
            numbers = -1;
    if (numbers < 0)
        return sam_fail(err, SAM_ERR_FORMAT,
                        "%s: OFF header line %d: expected vertex and face counts (and an edge count), found \"%.*s\"",
                        path, c.line_no, sam_mesh_text_shown(line, c.eol), line);
    /* OpenMesh reads the edge count whether or not it is there, and would
     * take the first coordinate for it. */
    if (numbers == 2)
        reshaped = 1;
    if (value[0] > size || value[1] > size)
        return sam_fail(err, SAM_ERR_FORMAT,
                        "%s: OFF header declares %llu vertices and %llu faces but the file has only %zu bytes", path,
                        value[0], value[1], size);
    if (value[0] == 0 || value[1] == 0)
        return sam_fail(err, SAM_ERR_EMPTY, "%s: OFF header declares %llu vertices and %llu faces", path, value[0],
                        value[1]);
    if (out) {
        char head[96];
        const int n = snprintf(head, sizeof head, "%.*s\n%llu %llu %llu\n", i + 3, kw, value[0], value[1], value[2]);
        sam_text_append(out, head, (size_t)n);
    }
    int base = 3 + 3 * normal + 2 * st_uv;
    for (unsigned long long v = 0; v < value[0]; ++v) {
        count = next_content_line(&c, &line, &eol, tok, len, OFF_MAX_TOKENS, &commented);
        if (count < 0)
            return sam_fail(err, SAM_ERR_FORMAT, "%s: OFF file is truncated: it ends before vertex %llu of %llu", path,
                            v, value[0]);
        int ok = count == base || (colour && (count == base + 3 || count == base + 4)), kind = 1, at = 0;
        for (int k = 0; k < count && count <= OFF_MAX_TOKENS && kind == 1; ++k)
            kind = sam_mesh_token_number(tok[k], len[k]), at = k;
        if (ok && kind < 0)
            return sam_fail(err, SAM_ERR_FORMAT, "%s: OFF line %d: vertex %llu: \"%.*s\" " SAM_MESH_NOT_A_FLOAT, path,
                            c.line_no, v, len[at] < 40 ? len[at] : 40, tok[at]);
        if (!ok || kind != 1)
            return sam_fail(err, SAM_ERR_FORMAT,
                            "%s: OFF line %d: vertex %llu must be %d finite numbers%s: \"%.*s\"", path, c.line_no, v,
                            base, colour ? " plus 3 or 4 colour values" : "", sam_mesh_text_shown(line, c.eol), line);
        if (out) {
            /* count <= base + 4 <= 12 here: every token is stored. */
            sam_text_append(out, tok[0], (size_t)(tok[count - 1] + len[count - 1] - tok[0]));
            sam_text_append(out, "\n", 1);
        }
    }
    for (unsigned long long f = 0; f < value[1]; ++f) {
        count = next_content_line(&c, &line, &eol, tok, len, OFF_MAX_TOKENS, &commented);
        if (count < 0)
            return sam_fail(err, SAM_ERR_FORMAT, "%s: OFF file is truncated: it ends before face %llu of %llu", path,
                            f, value[1]);
        /* k >= 3 corner indices, then a colour (an index into a colour map,
         * or 3 or 4 values) that OpenMesh is not given: the whole line is
         * checked, whatever its length. */
        unsigned long long corners;
        int ok = sam_mesh_token_count(tok[0], len[0], &corners) == 1 && corners >= 3 && corners < (unsigned long long)count;
        const unsigned long long extra = ok ? (unsigned long long)count - corners - 1 : 0;
        ok = ok && (extra == 0 || extra == 1 || extra == 3 || extra == 4);
        const char *p = line, *corners_end = line;
        for (int k = 0; ok && k < count; ++k) {
            const char *t[1] = {p};
            int l[1] = {0};
            while (*p == ' ' || *p == '\t')
                p++;
            sam_mesh_text_tokenize(p, eol, t, l, 1);
            unsigned long long index;
            if ((unsigned long long)k <= corners) {
                ok = sam_mesh_token_count(t[0], l[0], &index) == 1 && (k == 0 || index < value[0]);
                corners_end = t[0] + l[0];
            } else {
                ok = sam_mesh_token_number(t[0], l[0]) == 1;
            }
            p = t[0] + l[0];
        }
        if (!ok)
            return sam_fail(err, SAM_ERR_FORMAT,
                            "%s: OFF line %d: face %llu must be a corner count k >= 3, k vertex indices below %llu "
                            "and at most a colour (1, 3 or 4 numbers): \"%.*s\"",
                            path, c.line_no, f, value[0], sam_mesh_text_shown(line, c.eol), line);
        if (extra)
            reshaped = 1;
        if (out) {
            sam_text_append(out, tok[0], (size_t)(corners_end - tok[0]));
            sam_text_append(out, "\n", 1);
        }
    }
    expect->known = 1;
    expect->vertices = value[0];
    expect->faces = expect->file_faces = value[1];
    if (rewrite)
        *rewrite = reshaped || commented;
    return SAM_OK;
}

static sam_status preflight_off(const char *path, const char *data, size_t size, sam_mesh_expect *expect,
                                sam_error *err)
{
    sam_status st = sam_mesh_check_text(path, "OFF", data, size, err);
    int rewrite = 0;
    if (st == SAM_OK)
        st = walk_off(path, data, size, expect, NULL, &rewrite, err);
    if (st != SAM_OK || !rewrite)
        return st;
    sam_text out = {0};
    st = walk_off(path, data, size, expect, &out, NULL, err);
    return keep_rewrite(path, size, st, &out, ".off", expect, err);
}

/* ---- OBJ */

/* One OBJ index ("3", "-1"): 1-based against `count` elements so far,
 * negative counts back from the last. Its 0-based element goes to *at. */
static int obj_index_ok(const char *tok, int len, unsigned long long count, unsigned long long *at)
{
    int negative = len > 0 && tok[0] == '-';
    unsigned long long v;
    if (sam_mesh_token_count(tok + negative, len - negative, &v) != 1 || v < 1 || v > count)
        return 0;
    *at = negative ? count - v : v - 1;
    return 1;
}

#define OBJ_DISTINCT 3

/* Adds a face's corner vertex to the (up to 3) distinct ones seen. */
static void note_distinct(unsigned long long v, unsigned long long *seen, int *n)
{
    for (int i = 0; i < *n; ++i)
        if (seen[i] == v)
            return;
    if (*n < OBJ_DISTINCT)
        seen[(*n)++] = v;
}

/* A token sam_mesh_token_number accepted, as the float the reader stores. */
static float token_float(const char *tok, int len)
{
    char buf[64];
    memcpy(buf, tok, (size_t)len);
    buf[len] = 0;
    return strtof(buf, NULL);
}

static sam_status walk_obj(const char *path, const char *data, size_t size, sam_mesh_expect *expect, sam_error *err)
{
    sam_status st = sam_mesh_check_text(path, "OBJ", data, size, err);
    if (st != SAM_OK)
        return st;
    sam_mesh_text_cursor c = {data, data + size, 0, data};
    const char *line, *eol;
    unsigned long long nv = 0, nt = 0, nn = 0;
    sam_mesh_obj_gather g = {1, 0, 0, 0, 0, 0, 0};
    sam_mesh_obj_colors colors = {0, 1, 0.0f};
    sam_mesh_obj_materials materials = {SAM_MESH_NO_MATERIAL, 0};
    while (sam_mesh_text_next_line(&c, &line, &eol)) {
        const char *tok[16];
        int len[16];
        int count = sam_mesh_text_tokenize(line, eol, tok, len, 16);
        if (count == 0)
            continue;
        int s = sam_mesh_text_shown(line, eol), values = 0;
        unsigned long long *counter = NULL;
        if (sam_mesh_token_is(tok[0], len[0], "v"))
            counter = &nv, values = 3;
        else if (sam_mesh_token_is(tok[0], len[0], "vt"))
            counter = &nt, values = 1;
        else if (sam_mesh_token_is(tok[0], len[0], "vn"))
            counter = &nn, values = 3;
        if (counter) {
            if (count - 1 < values)
                return sam_fail(err, SAM_ERR_FORMAT, "%s: OBJ line %d: expected %d numbers: \"%.*s\"", path,
                                c.line_no, values, s, line);
            for (int i = 1; i <= values; ++i) {
                int kind = sam_mesh_token_number(tok[i], len[i]);
                if (kind <= 0)
                    return sam_fail(err, SAM_ERR_FORMAT, "%s: OBJ line %d: \"%.*s\" %s", path, c.line_no,
                                    len[i] < 40 ? len[i] : 40, tok[i], kind < 0 ? SAM_MESH_NOT_A_FLOAT : "is not a valid number");
            }
            if (counter == &nv) {
                /* "v x y z r g b" (MeshLab's, ZBrush's, many scanners'). */
                int colored = count == 7;
                for (int i = 4; colored && i < 7; ++i)
                    colored = sam_mesh_token_number(tok[i], len[i]) > 0;
                float rgb[3] = {0, 0, 0};
                for (int k = 0; colored && k < 3; ++k)
                    rgb[k] = token_float(tok[4 + k], len[4 + k]);
                if (!sam_mesh_obj_gather_color(expect, &colors, nv, colored ? rgb : NULL))
                    return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for the OBJ's vertex colours",
                                    path);
            }
            if (counter == &nn) {
                const float v[3] = {token_float(tok[1], len[1]), token_float(tok[2], len[2]),
                                    token_float(tok[3], len[3])};
                if (!sam_mesh_obj_gather_normal(expect, &g, nn, v))
                    return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for the OBJ's normals", path);
            }
            (*counter)++;
            continue;
        }
        if (sam_mesh_token_is(tok[0], len[0], "usemtl") && count > 1 &&
            !sam_mesh_obj_use_material(expect, &materials, tok[1], eol))
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for the OBJ's materials", path);
        if (!sam_mesh_token_is(tok[0], len[0], "f"))
            continue; /* groups, smoothing, lines: not geometry we read */
        /* Corners: v, v/t, v//n or v/t/n; all corners of a face alike.
         * OpenMesh drops repeated corners, and a face left with fewer
         * than 3. */
        const char *p = line + 1;
        int corner = 0, distinct = 0;
        unsigned long long seen[OBJ_DISTINCT], vertex, unused, normal = 0;
        while (p < eol) {
            while (p < eol && (*p == ' ' || *p == '\t'))
                p++;
            if (p >= eol)
                break;
            const char *part[3] = {p, NULL, NULL};
            int plen[3] = {0, 0, 0}, parts = 1;
            while (p < eol && *p != ' ' && *p != '\t') {
                if (*p == '/') {
                    if (parts == 3)
                        goto bad_corner;
                    plen[parts - 1] = (int)(p - part[parts - 1]);
                    part[parts++] = p + 1;
                }
                p++;
            }
            plen[parts - 1] = (int)(p - part[parts - 1]);
            if (!obj_index_ok(part[0], plen[0], nv, &vertex) ||
                (parts >= 2 && plen[1] && !obj_index_ok(part[1], plen[1], nt, &unused)) ||
                (parts == 3 && !obj_index_ok(part[2], plen[2], nn, &normal)) || (parts == 2 && !plen[1]))
                goto bad_corner;
            note_distinct(vertex, seen, &distinct);
            if (!sam_mesh_obj_gather_corner(expect, &g, (uint32_t)corner, vertex, parts == 3, normal))
                return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for the OBJ's corners", path);
            corner++;
            continue;
        bad_corner:
            return sam_fail(err, SAM_ERR_FORMAT,
                            "%s: OBJ line %d: face corner %d is not a valid index (v, v/t, v//n or v/t/n with "
                            "%llu positions, %llu texture coordinates, %llu normals so far): \"%.*s\"",
                            path, c.line_no, corner + 1, nv, nt, nn, s, line);
        }
        expect->file_faces++;
        if (distinct < 3 && expect->repeated_corner_faces++ == 0)
            expect->first_repeated_line = c.line_no;
        if (distinct >= 3 && (!sam_mesh_obj_gather_face(expect, &g, (uint32_t)corner) ||
                              !sam_mesh_obj_face_material(expect, &materials,
                                                 expect->file_faces - 1 - expect->repeated_corner_faces)))
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for the OBJ's corners", path);
    }
    sam_mesh_obj_gather_finish(expect, &g);
    sam_mesh_obj_colors_finish(expect, &colors, nv);
    expect->known = 1;
    expect->vertices = nv;
    expect->faces = expect->file_faces - expect->repeated_corner_faces;
    return SAM_OK;
}

/* OpenMesh's OBJ reader takes every word of a face line for a corner, so a
 * comment after a face ("f 1 2 3 # lid") was refused, and it knows no
 * continued lines (a line ending in a backslash, which the OBJ
 * specification allows for long faces). Such a file is written again for
 * it (sam_mesh_expect.rewritten), byte for byte as long and line for line
 * where it was, so that messages name the file's own lines: a comment
 * after content becomes blanks, and each backslash and the line end after
 * it join the lines, the line end moving to the end of the joined line.
 * Returns the text, or NULL when the file needs none (*oom set when out of
 * memory). */
static char *obj_plain_text(const char *data, size_t size, int *oom)
{
    *oom = 0;
    int needed = 0;
    for (size_t i = 0; i < size && !needed; ++i)
        needed = data[i] == '\\' || data[i] == '#';
    if (!needed)
        return NULL;
    char *out = malloc(size + 1);
    if (!out) {
        *oom = 1;
        return NULL;
    }
    size_t o = 0;
    /* Line ends held back; a word seen on the line; inside a comment (no
     * backslash continues it), blanked when after a word. */
    int held = 0, content = 0, comment = 0, blank = 0;
    for (size_t i = 0; i < size; ++i) {
        const char ch = data[i];
        const int crlf = ch == '\\' && i + 2 < size && data[i + 1] == '\r' && data[i + 2] == '\n';
        if (!comment && ch == '\\' && (crlf || (i + 1 < size && data[i + 1] == '\n'))) {
            out[o++] = ' ';
            if (crlf)
                out[o++] = ' '; /* the CR's place */
            i += 1 + crlf;      /* the line end waits for the joined line's */
            held++;
            continue;
        }
        if (ch == '\n') {
            for (; held > 0; --held)
                out[o++] = '\n';
            out[o++] = '\n';
            content = comment = blank = 0;
            continue;
        }
        if (ch == '#' && !comment)
            comment = 1, blank = content;
        if (ch != ' ' && ch != '\t' && ch != '\r')
            content = 1;
        out[o++] = blank && ch != '\r' ? ' ' : ch;
    }
    for (; held > 0; --held)
        out[o++] = '\n';
    out[o] = '\0';
    if (!memcmp(out, data, size)) {
        free(out);
        return NULL;
    }
    /* OpenMesh would look for the material library beside the temporary
     * file, where anyone may have put one; materials are read from the
     * file's own folder (sam_mesh_load_albedo), so the line goes. */
    for (char *line = out; line && line < out + size;) {
        char *end = memchr(line, '\n', (size_t)(out + size - line));
        const size_t len = end ? (size_t)(end - line) : (size_t)(out + size - line);
        const char *word = line + strspn(line, " \t");
        if (!strncmp(word, "mtllib", 6) && (word[6] == ' ' || word[6] == '\t'))
            memset(line, ' ', len && line[len - 1] == '\r' ? len - 1 : len);
        line = end ? end + 1 : NULL;
    }
    return out;
}

static sam_status preflight_obj(const char *path, const char *data, size_t size, sam_mesh_expect *expect,
                                sam_error *err)
{
    int oom;
    char *plain = obj_plain_text(data, size, &oom);
    if (oom)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory (%zu bytes)", path, size);
    if (!plain)
        return walk_obj(path, data, size, expect, err);
    sam_text out = {plain, size, size + 1, 0};
    return keep_rewrite(path, size, walk_obj(path, plain, size, expect, err), &out, ".obj", expect, err);
}

/* ---- STL */

/* Binary STL: an 80-byte header, a u32 count, 50 bytes per triangle (a
 * normal, three vertices, two attribute bytes); every vertex coordinate
 * must be finite. ASCII STL: the numbers of every vertex line must fit a
 * float. */
static sam_status preflight_stl(const char *path, const char *data, size_t size, sam_error *err)
{
    const unsigned char *u = (const unsigned char *)data;
    uint32_t n = size >= 84 ? (uint32_t)u[80] | (uint32_t)u[81] << 8 | (uint32_t)u[82] << 16 | (uint32_t)u[83] << 24
                            : 0;
    /* Binary files may begin with "solid" too; their size tells them apart. */
    if (size >= 5 && !memcmp(data, "solid", 5) && !(size >= 84 && 84ull + 50ull * n == size)) {
        sam_mesh_text_cursor c = {data, data + size, 0, data};
        const char *line, *eol;
        while (sam_mesh_text_next_line(&c, &line, &eol)) {
            const char *tok[5];
            int len[5];
            int count = sam_mesh_text_tokenize(line, eol, tok, len, 5);
            if (count < 1 || !sam_mesh_token_is(tok[0], len[0], "vertex"))
                continue;
            for (int k = 1; k < count && k < 5; ++k) {
                const int kind = sam_mesh_token_number(tok[k], len[k]);
                if (kind != 1)
                    return sam_fail(err, SAM_ERR_FORMAT, "%s: STL line %d: \"%.*s\" %s", path, c.line_no,
                                    len[k] < 40 ? len[k] : 40, tok[k], kind ? SAM_MESH_NOT_A_FLOAT : "is not a number");
            }
            if (count != 4)
                return sam_fail(err, SAM_ERR_FORMAT, "%s: STL line %d: a vertex takes 3 numbers: \"%.*s\"", path,
                                c.line_no, sam_mesh_text_shown(line, eol), line);
        }
        return SAM_OK;
    }
    if (size < 84)
        return sam_fail(err, SAM_ERR_FORMAT, "%s: binary STL is truncated: %zu bytes, the header alone is 84", path,
                        size);
    if (84ull + 50ull * n > size)
        return sam_fail(err, SAM_ERR_FORMAT,
                        "%s: binary STL declares %u triangles (%llu bytes) but the file has only %zu bytes", path, n,
                        84ull + 50ull * n, size);
    for (uint32_t t = 0; t < n; ++t)
        for (int k = 3; k < 12; ++k) {
            const unsigned char *b = u + 84 + 50 * (size_t)t + 4 * (size_t)k;
            const uint32_t bits = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
            float f;
            memcpy(&f, &bits, sizeof f);
            if (!isfinite(f))
                return sam_fail(err, SAM_ERR_FORMAT, "%s: binary STL triangle %u, vertex %d has a non-finite coordinate "
                                "(%g)", path, t, k / 3 - 1, (double)f);
        }
    return SAM_OK;
}

sam_status sam_mesh_preflight(const char *path, sam_mesh_expect *expect, sam_error *err)
{
    memset(expect, 0, sizeof *expect);
    int ply = sam_path_has_extension(path, ".ply"), off = sam_path_has_extension(path, ".off");
    int stl = sam_path_has_extension(path, ".stl"), obj = sam_path_has_extension(path, ".obj");
    if (!ply && !off && !stl && !obj)
        return SAM_OK;
    uint8_t *data;
    size_t size;
    if (sam_read_file(path, &data, &size, NULL) != SAM_OK)
        return SAM_OK; /* the reader reports why it cannot read the file */
    sam_status st = SAM_OK;
    if (size == 0)
        st = SAM_OK; /* the reader reports an empty file */
    else if (ply)
        st = preflight_ply(path, (const char *)data, size, expect, err);
    else if (off)
        st = preflight_off(path, (const char *)data, size, expect, err);
    else if (obj)
        st = preflight_obj(path, (const char *)data, size, expect, err);
    else
        st = preflight_stl(path, (const char *)data, size, err);
    if (st != SAM_OK) {
        sam_mesh_expect_free(expect);
        memset(expect, 0, sizeof *expect);
    }
    free(data);
    return st;
}
