/* sam_view's scripted input (sam_view_script.h). */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <GLFW/glfw3.h>

#include "sam/sam_view_script.h"

#define MAX_WORDS 8
#define WORD_MAX 1100

typedef struct line_words {
    int count;
    char word[MAX_WORDS][WORD_MAX];
} line_words;

/* Splits one line (comment removed) into words; 0 when a word is too long
 * or there are too many. */
static int split(const char *line, size_t n, line_words *w)
{
    w->count = 0;
    size_t i = 0;
    while (i < n) {
        while (i < n && isspace((unsigned char)line[i]))
            ++i;
        if (i == n)
            break;
        size_t start = i;
        while (i < n && !isspace((unsigned char)line[i]))
            ++i;
        if (w->count == MAX_WORDS || i - start >= WORD_MAX)
            return 0;
        memcpy(w->word[w->count], line + start, i - start);
        w->word[w->count][i - start] = 0;
        ++w->count;
    }
    return 1;
}

static int parse_number(const char *s, double lo, double hi, double *out)
{
    char *end;
    double v = strtod(s, &end);
    if (end == s || *end || !isfinite(v) || v < lo || v > hi)
        return 0;
    *out = v;
    return 1;
}

static int key_code(const char *name)
{
    static const struct {
        const char *name;
        int key;
    } named[] = {{"SPACE", GLFW_KEY_SPACE}, {"ESCAPE", GLFW_KEY_ESCAPE}, {"ENTER", GLFW_KEY_ENTER},
                 {"TAB", GLFW_KEY_TAB},     {"LEFT", GLFW_KEY_LEFT},     {"RIGHT", GLFW_KEY_RIGHT},
                 {"UP", GLFW_KEY_UP},       {"DOWN", GLFW_KEY_DOWN},     {"[", GLFW_KEY_LEFT_BRACKET},
                 {"]", GLFW_KEY_RIGHT_BRACKET}, {",", GLFW_KEY_COMMA},   {".", GLFW_KEY_PERIOD},
                 {"-", GLFW_KEY_MINUS},     {"=", GLFW_KEY_EQUAL},       {"/", GLFW_KEY_SLASH}};
    for (size_t i = 0; i < sizeof named / sizeof named[0]; ++i)
        if (!strcasecmp(name, named[i].name))
            return named[i].key;
    if (name[0] && !name[1]) {
        int c = toupper((unsigned char)name[0]);
        if (c >= 'A' && c <= 'Z')
            return GLFW_KEY_A + (c - 'A');
        if (c >= '0' && c <= '9')
            return GLFW_KEY_0 + (c - '0');
    }
    if (toupper((unsigned char)name[0]) == 'F' && name[1]) {
        char *end;
        long f = strtol(name + 1, &end, 10);
        if (!*end && f >= 1 && f <= 12)
            return GLFW_KEY_F1 + (int)(f - 1);
    }
    return -1;
}

/* One event from a line's words (at least two: time and action). */
static sam_status parse_event(const line_words *w, const char *name, int line, sam_view_event *e, sam_error *err)
{
    static const struct {
        const char *name;
        sam_view_action action;
        int args;
    } actions[] = {{"key", SAM_VIEW_KEY, 1},       {"mouse", SAM_VIEW_MOUSE, 2},
                   {"drag", SAM_VIEW_DRAG, 5},     {"scroll", SAM_VIEW_SCROLL, 1},
                   {"resize", SAM_VIEW_RESIZE, 2}, {"screenshot", SAM_VIEW_SCREENSHOT, 1},
                   {"lose-context", SAM_VIEW_LOSE_CONTEXT, 0}, {"quit", SAM_VIEW_QUIT, 0}};
    memset(e, 0, sizeof *e);
    e->line = line;
    if (!parse_number(w->word[0], 0, 1e6, &e->time_s))
        return sam_fail(err, SAM_ERR_FORMAT, "%s:%d: expected a time in seconds in [0, 1e6], found \"%s\"", name,
                        line, w->word[0]);
    int found = -1;
    for (size_t i = 0; i < sizeof actions / sizeof actions[0]; ++i)
        if (!strcmp(w->word[1], actions[i].name))
            found = (int)i;
    if (found < 0)
        return sam_fail(err, SAM_ERR_FORMAT,
                        "%s:%d: unknown action \"%s\" (expected key, mouse, drag, scroll, resize, screenshot, "
                        "lose-context or quit)",
                        name, line, w->word[1]);
    e->action = actions[found].action;
    if (w->count - 2 != actions[found].args)
        return sam_fail(err, SAM_ERR_FORMAT, "%s:%d: %s takes %d argument%s, found %d", name, line, w->word[1],
                        actions[found].args, actions[found].args == 1 ? "" : "s", w->count - 2);
    const char *a = w->word[2];
    double v[5] = {0};
    switch (e->action) {
    case SAM_VIEW_KEY: {
        for (;;) {
            if (!strncasecmp(a, "shift+", 6) && a[6]) {
                e->mods |= GLFW_MOD_SHIFT;
                a += 6;
            } else if (!strncasecmp(a, "ctrl+", 5) && a[5]) {
                e->mods |= GLFW_MOD_CONTROL;
                a += 5;
            } else {
                break;
            }
        }
        if ((e->key = key_code(a)) < 0)
            return sam_fail(err, SAM_ERR_FORMAT,
                            "%s:%d: unknown key \"%s\" (a letter, a digit, [ ] , . - = /, SPACE, ESCAPE, ENTER, "
                            "TAB, LEFT, RIGHT, UP, DOWN or F1..F12)",
                            name, line, a);
        return SAM_OK;
    }
    case SAM_VIEW_DRAG:
        if (!strcmp(a, "left"))
            e->button = GLFW_MOUSE_BUTTON_LEFT;
        else if (!strcmp(a, "right"))
            e->button = GLFW_MOUSE_BUTTON_RIGHT;
        else if (!strcmp(a, "middle"))
            e->button = GLFW_MOUSE_BUTTON_MIDDLE;
        else
            return sam_fail(err, SAM_ERR_FORMAT, "%s:%d: unknown button \"%s\" (expected left, right or middle)",
                            name, line, a);
        for (int i = 0; i < 4; ++i)
            if (!parse_number(w->word[3 + i], -1e5, 1e5, &v[i]))
                return sam_fail(err, SAM_ERR_FORMAT, "%s:%d: drag: expected a pixel coordinate, found \"%s\"", name,
                                line, w->word[3 + i]);
        e->x0 = (float)v[0], e->y0 = (float)v[1], e->x1 = (float)v[2], e->y1 = (float)v[3];
        return SAM_OK;
    case SAM_VIEW_MOUSE:
        for (int i = 0; i < 2; ++i)
            if (!parse_number(w->word[2 + i], -1e5, 1e5, &v[i]))
                return sam_fail(err, SAM_ERR_FORMAT, "%s:%d: mouse: expected a pixel coordinate, found \"%s\"", name,
                                line, w->word[2 + i]);
        e->x0 = (float)v[0], e->y0 = (float)v[1];
        return SAM_OK;
    case SAM_VIEW_SCROLL:
        if (!parse_number(a, -100, 100, &v[0]))
            return sam_fail(err, SAM_ERR_FORMAT, "%s:%d: scroll: expected notches in [-100, 100], found \"%s\"",
                            name, line, a);
        e->y0 = (float)v[0];
        return SAM_OK;
    case SAM_VIEW_RESIZE:
        for (int i = 0; i < 2; ++i)
            if (!parse_number(w->word[2 + i], 1, 16384, &v[i]) || v[i] != floor(v[i]))
                return sam_fail(err, SAM_ERR_FORMAT, "%s:%d: resize: expected a size in 1..16384, found \"%s\"", name,
                                line, w->word[2 + i]);
        e->x0 = (float)v[0], e->y0 = (float)v[1];
        return SAM_OK;
    case SAM_VIEW_SCREENSHOT:
        if (strlen(a) >= sizeof e->path)
            return sam_fail(err, SAM_ERR_FORMAT, "%s:%d: screenshot prefix is %zu bytes, the limit is %zu", name,
                            line, strlen(a), sizeof e->path - 1);
        memcpy(e->path, a, strlen(a) + 1);
        return SAM_OK;
    case SAM_VIEW_LOSE_CONTEXT:
    case SAM_VIEW_QUIT:
        return SAM_OK;
    }
    return SAM_OK;
}

sam_status sam_view_script_parse(const char *text, size_t size, const char *name, sam_view_event **events,
                                 size_t *count, sam_error *err)
{
    if (!events || !count || (!text && size))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "script: NULL text or outputs");
    *events = NULL;
    *count = 0;
    name = name ? name : "script";
    sam_view_event *list = NULL;
    size_t n = 0, cap = 0;
    line_words *w = malloc(sizeof *w);
    if (!w)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory", name);
    sam_status st = SAM_OK;
    size_t pos = 0;
    for (int line = 1; pos < size && st == SAM_OK; ++line) {
        size_t end = pos;
        while (end < size && text[end] != '\n')
            ++end;
        size_t len = end - pos;
        const char *hash = memchr(text + pos, '#', len);
        if (hash)
            len = (size_t)(hash - (text + pos));
        if (!split(text + pos, len, w)) {
            st = sam_fail(err, SAM_ERR_FORMAT, "%s:%d: more than %d words, or a word of %d bytes or more", name,
                          line, MAX_WORDS, WORD_MAX);
        } else if (w->count == 1) {
            st = sam_fail(err, SAM_ERR_FORMAT, "%s:%d: expected TIME ACTION [ARGS], found only \"%s\"", name, line,
                          w->word[0]);
        } else if (w->count > 1) {
            if (n == cap) {
                size_t grown = cap ? 2 * cap : 16;
                sam_view_event *more = realloc(list, grown * sizeof *more);
                if (!more) {
                    st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory at line %d", name, line);
                    break;
                }
                list = more;
                cap = grown;
            }
            st = parse_event(w, name, line, &list[n], err);
            if (st == SAM_OK && n > 0 && list[n].time_s < list[n - 1].time_s)
                st = sam_fail(err, SAM_ERR_FORMAT, "%s:%d: time %g s is before the previous event's %g s", name, line,
                              list[n].time_s, list[n - 1].time_s);
            n += st == SAM_OK;
        }
        pos = end + 1;
    }
    free(w);
    if (st != SAM_OK) {
        free(list);
        return st;
    }
    *events = list;
    *count = n;
    return SAM_OK;
}

sam_status sam_view_script_load(const char *path, sam_view_event **events, size_t *count, sam_error *err)
{
    if (!path || !events || !count)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "script: NULL path or outputs");
    *events = NULL;
    *count = 0;
    uint8_t *data;
    size_t size;
    sam_status st = sam_read_file(path, &data, &size, err);
    if (st != SAM_OK)
        return st;
    st = sam_view_script_parse((const char *)data, size, path, events, count, err);
    free(data);
    return st;
}
