/*
 * The text scanning with which the mesh pre-check (sam_mesh_preflight.c)
 * walks OBJ, OFF and PLY text: lines and their blank-separated words, the
 * stream of whitespace-separated tokens that C++ stream extraction (and so
 * OpenMesh) reads, and counts and numbers as OpenMesh reads them. The
 * small scanners are inline: the walk calls them for every token of a
 * scan.
 */
#ifndef SAM_MESH_TEXT_H
#define SAM_MESH_TEXT_H

#include <ctype.h>
#include <stddef.h>
#include <string.h>

#include "sam/sam_common.h"

typedef struct sam_mesh_text_cursor {
    const char *p, *end;
    int line_no;
    const char *eol; /* where the last line read ends, for messages that quote it whole */
} sam_mesh_text_cursor;

/* Next line [*line, *eol) without its newline (and CR); 0 at the end. */
static inline int sam_mesh_text_next_line(sam_mesh_text_cursor *c, const char **line, const char **eol)
{
    if (c->p >= c->end)
        return 0;
    *line = c->p;
    while (c->p < c->end && *c->p != '\n')
        c->p++;
    *eol = c->p;
    if (c->p < c->end)
        c->p++;
    if (*eol > *line && (*eol)[-1] == '\r')
        (*eol)--;
    c->eol = *eol;
    c->line_no++;
    return 1;
}

/* Splits [line, eol) into blank-separated tokens; stores at most `max`,
 * returns how many there are. */
static inline int sam_mesh_text_tokenize(const char *line, const char *eol, const char **tok, int *len, int max)
{
    int count = 0;
    const char *p = line;
    for (;;) {
        while (p < eol && (*p == ' ' || *p == '\t'))
            p++;
        if (p >= eol)
            return count;
        const char *start = p;
        while (p < eol && *p != ' ' && *p != '\t')
            p++;
        if (count < max) {
            tok[count] = start;
            len[count] = (int)(p - start);
        }
        count++;
    }
}

/* A stream of whitespace-separated tokens, as C++ stream extraction (and
 * so OpenMesh) reads them. */
typedef struct sam_mesh_token_stream {
    const char *p, *end;
} sam_mesh_token_stream;

static inline int sam_mesh_next_token(sam_mesh_token_stream *ts, const char **tok, int *len)
{
    while (ts->p < ts->end && isspace((unsigned char)*ts->p))
        ts->p++;
    if (ts->p >= ts->end)
        return 0;
    *tok = ts->p;
    while (ts->p < ts->end && !isspace((unsigned char)*ts->p))
        ts->p++;
    *len = (int)(ts->p - *tok);
    return 1;
}

static inline int sam_mesh_token_is(const char *tok, int len, const char *word)
{
    return len == (int)strlen(word) && !strncmp(tok, word, (size_t)len);
}

/* A whole token of decimal digits: 1, with its value; 0 when it is not
 * one; -1 when its value passes 2^64 - 1. */
static inline int sam_mesh_token_count(const char *tok, int len, unsigned long long *out)
{
    unsigned long long v = 0;
    int overflow = 0;
    if (len <= 0)
        return 0;
    for (int i = 0; i < len; ++i) {
        if (!isdigit((unsigned char)tok[i]))
            return 0;
        const unsigned long long digit = (unsigned long long)(tok[i] - '0');
        if (v > (~0ull - digit) / 10)
            overflow = 1;
        v = v * 10 + digit;
    }
    *out = v;
    return overflow ? -1 : 1;
}

/* How much of the line [line, eol) a message quotes: at most 80 bytes. */
static inline int sam_mesh_text_shown(const char *line, const char *eol)
{
    return eol - line < 80 ? (int)(eol - line) : 80;
}

/* A whole token read as a number: 1 when it is a decimal number that fits
 * a 32-bit float (finite, at most FLT_MAX in size; smaller ones round to 0
 * or a subnormal, as a float reader gives them), -1 when it is a number
 * that does not, 0 when it is no decimal number. */
int sam_mesh_token_number(const char *tok, int len);

/* What a message says of a token sam_mesh_token_number gave -1. */
#define SAM_MESH_NOT_A_FLOAT "is not a finite number that fits a 32-bit float (at most 3.4e38 in size)"

/* Text formats hold printable characters, blanks and line ends (LF or
 * CRLF; and UTF-8 in comments); a control character means a damaged or
 * binary file, on which OpenMesh's stream parsing and ours would disagree
 * (a lone CR in a PLY header sent OpenMesh into an endless loop). */
sam_status sam_mesh_check_text(const char *path, const char *kind, const char *data, size_t size, sam_error *err);

#endif
