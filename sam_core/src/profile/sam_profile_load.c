/*
 * sam_profile_load: user profile files, JSON (read with sam_json) or text. The
 * formats are described in sam_profile.h. Every value is validated before
 * the profile is built, and every error names the file and the key path or
 * line together with the value found.
 */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_json.h"
#include "sam/sam_profile.h"
#include "sam_profile_internal.h"

static const char rgb_names[3] = {'r', 'g', 'b'};

/* The profile's default name: the file name without its extension, cut at
 * a UTF-8 character boundary when too long. */
static void default_name(const char *path, char name[SAM_PROFILE_NAME_SIZE])
{
    const char *base = sam_path_basename(path);
    size_t len = strlen(base);
    const char *dot = strrchr(base, '.');
    if (dot && dot != base)
        len = (size_t)(dot - base);
    if (len > SAM_PROFILE_NAME_SIZE - 1) {
        len = SAM_PROFILE_NAME_SIZE - 1;
        while (len > 0 && ((unsigned char)base[len] & 0xC0) == 0x80)
            len--;
    }
    memset(name, 0, SAM_PROFILE_NAME_SIZE);
    memcpy(name, base, len);
}

/* Replaces the name; the rest of the buffer is zeroed so that profiles
 * compare equal bytewise. */
static void replace_name(char name[SAM_PROFILE_NAME_SIZE], const char *src, size_t len)
{
    memset(name, 0, SAM_PROFILE_NAME_SIZE);
    memcpy(name, src, len);
}

/* Up to `max` bytes of `s` (stopping at NUL) with control characters shown
 * as \xNN, so that an error message stays one readable line. */
#define SHOWN_SIZE 96
static const char *shown(const char *s, size_t max, char out[SHOWN_SIZE])
{
    size_t o = 0;
    for (size_t i = 0; i < max && s[i] && o + 5 < SHOWN_SIZE; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c < 0x20 || c == 0x7f)
            o += (size_t)snprintf(out + o, SHOWN_SIZE - o, "\\x%02x", c);
        else
            out[o++] = (char)c;
    }
    out[o] = 0;
    return out;
}

/* ---------------------------------------------------------------------- */
/* JSON                                                                   */

/* Finds the `count` `keys` among an object's members: `found` receives,
 * per key, the member or NULL. Unknown and duplicate keys are errors,
 * worded as profile files have always worded them. */
static sam_status json_members(const sam_json_ctx *ctx, const cJSON *object, const char *where,
                               const char *const *keys, size_t count, const cJSON **found)
{
    int duplicate;
    const cJSON *bad = sam_json_bad_key(object, keys, count, &duplicate);
    if (bad) {
        char name_shown[SHOWN_SIZE], at[SAM_ERROR_MESSAGE_SIZE];
        const char *name = duplicate ? bad->string : shown(bad->string, 64, name_shown);
        sam_json_key_path(at, sizeof at, where, name);
        return sam_json_fail(ctx, SAM_ERR_FORMAT, at, duplicate ? "duplicate key" : "unknown key");
    }
    for (size_t k = 0; k < count; k++)
        found[k] = cJSON_GetObjectItemCaseSensitive(object, keys[k]);
    return SAM_OK;
}

enum {
    KEY_TYPE, KEY_KIND, KEY_NAME, KEY_GAUSSIANS, KEY_SSP, KEY_SA, KEY_ETA, KEY_ALBEDO, KEY_MFP, KEY_RADIUS,
    KEY_TABLE_R, KEY_TABLE_RD, KEY_COUNT
};

/* The profile types, the keys each takes (bits of 1 << KEY_...) and the
 * keys it needs; a Burley material needs one of its two distances. */
enum { TYPE_GAUSSIANS, TYPE_DIPOLE, TYPE_BURLEY, TYPE_TABLE, TYPE_COUNT };
static const char *const type_names[TYPE_COUNT] = {"gaussians", "dipole", "burley", "table"};
static const unsigned type_keys[TYPE_COUNT] = {
    1u << KEY_GAUSSIANS,
    1u << KEY_SSP | 1u << KEY_SA | 1u << KEY_ETA,
    1u << KEY_ALBEDO | 1u << KEY_MFP | 1u << KEY_RADIUS,
    1u << KEY_TABLE_R | 1u << KEY_TABLE_RD,
};
static const unsigned type_required[TYPE_COUNT] = {
    1u << KEY_GAUSSIANS,
    1u << KEY_SSP | 1u << KEY_SA | 1u << KEY_ETA,
    1u << KEY_ALBEDO,
    1u << KEY_TABLE_R | 1u << KEY_TABLE_RD,
};

/* "radius_mm": [r...] and "rd": [[r, g, b]...] of one length. */
static sam_status json_table(const sam_json_ctx *ctx, const cJSON *radius, const cJSON *rd, sam_profile *out)
{
    static const char *const names[2] = {"radius_mm", "rd"};
    const cJSON *lists[2] = {radius, rd};
    for (int k = 0; k < 2; k++) {
        if (!cJSON_IsArray(lists[k]))
            return sam_json_fail(ctx, SAM_ERR_FORMAT, names[k], "expected an array, found %s",
                                 sam_json_kind(lists[k]));
        int n = cJSON_GetArraySize(lists[k]);
        if (n < 2 || n > SAM_PROFILE_MAX_TABLE)
            return sam_json_fail(ctx, SAM_ERR_FORMAT, names[k], "%d entries, expected 2..%d", n,
                                 SAM_PROFILE_MAX_TABLE);
    }
    const int n = cJSON_GetArraySize(radius);
    if (cJSON_GetArraySize(rd) != n)
        return sam_json_fail(ctx, SAM_ERR_FORMAT, "rd", "%d entries, but radius_mm has %d", cJSON_GetArraySize(rd),
                             n);
    float *r = malloc((size_t)n * sizeof *r);
    float(*v)[3] = malloc((size_t)n * sizeof *v);
    sam_status s = r && v ? SAM_OK : sam_fail(ctx->err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory", ctx->name);
    int i = 0;
    for (const cJSON *a = radius->child, *b = rd->child; s == SAM_OK && a && b; a = a->next, b = b->next, i++) {
        char where[64];
        if ((s = sam_json_checked_number(ctx, a, sam_json_index_path(where, sizeof where, "radius_mm", i),
                                         sam_profile_check_weight, &r[i])) == SAM_OK)
            s = sam_json_checked_rgb(ctx, b, sam_json_index_path(where, sizeof where, "rd", i),
                                     sam_profile_check_weight, v[i]);
    }
    sam_error inner;
    const float(*cv)[3] = v;
    if (s == SAM_OK && sam_profile_table((uint32_t)n, r, cv, out, &inner) != SAM_OK)
        s = sam_fail(ctx->err, SAM_ERR_FORMAT, "%s: %s", ctx->name, inner.message);
    free(r);
    free(v);
    return s;
}

static sam_status json_gaussians(const sam_json_ctx *ctx, const cJSON *list, sam_profile *out)
{
    static const char *const keys[] = {"variance", "weight"};
    if (!cJSON_IsArray(list))
        return sam_json_fail(ctx, SAM_ERR_FORMAT, "gaussians", "expected an array, found %s", sam_json_kind(list));
    int n = cJSON_GetArraySize(list);
    if (n < 1 || n > SAM_PROFILE_MAX_GAUSSIANS)
        return sam_json_fail(ctx, SAM_ERR_FORMAT, "gaussians", "%d entries, expected 1..%d", n,
                             SAM_PROFILE_MAX_GAUSSIANS);
    float variance[SAM_PROFILE_MAX_GAUSSIANS], weight[SAM_PROFILE_MAX_GAUSSIANS][3];
    int i = 0;
    for (const cJSON *g = list->child; g; g = g->next, i++) {
        char where[64], key[96];
        sam_json_index_path(where, sizeof where, "gaussians", i);
        if (!cJSON_IsObject(g))
            return sam_json_fail(ctx, SAM_ERR_FORMAT, where, "expected an object, found %s", sam_json_kind(g));
        const cJSON *found[2] = {NULL, NULL};
        sam_status s = json_members(ctx, g, where, keys, 2, found);
        if (s != SAM_OK)
            return s;
        for (int k = 0; k < 2; k++)
            if (!found[k])
                return sam_json_fail(ctx, SAM_ERR_FORMAT, where, "missing key \"%s\"", keys[k]);
        s = sam_json_checked_number(ctx, found[0], sam_json_key_path(key, sizeof key, where, "variance"),
                                    sam_profile_check_variance, &variance[i]);
        if (s != SAM_OK)
            return s;
        s = sam_json_checked_rgb(ctx, found[1], sam_json_key_path(key, sizeof key, where, "weight"),
                                 sam_profile_check_weight, weight[i]);
        if (s != SAM_OK)
            return s;
    }
    sam_error inner;
    const float(*w)[3] = weight;
    if (sam_profile_gaussian_sum((uint32_t)n, variance, w, out, &inner) != SAM_OK)
        return sam_fail(ctx->err, SAM_ERR_FORMAT, "%s: %s", ctx->name, inner.message);
    return SAM_OK;
}

static sam_status load_json(const char *path, const char *text, size_t size, sam_profile *out,
                            sam_error *err)
{
    static const char *const keys[KEY_COUNT] = {"type",   "kind",           "name",           "gaussians",
                                                "sigma_s_prime", "sigma_a", "eta",     "albedo",
                                                "mean_free_path", "scatter_radius", "radius_mm", "rd"};
    sam_json_ctx ctx = {path, err};
    const char *end = NULL;
    /* The length includes the NUL that sam_read_file appends, so cJSON's
     * "nothing after the value" check has a terminator to find. */
    cJSON *root = cJSON_ParseWithLengthOpts(text, size + 1, &end, 1);
    if (!root) {
        size_t at = (end && end >= text && end <= text + size) ? (size_t)(end - text) : size;
        size_t line, column;
        sam_json_line_column(text, at, &line, &column);
        if (sam_json_too_deep(text, size))
            return sam_fail(err, SAM_ERR_FORMAT, "%s:%zu:%zu: objects and arrays nest deeper than %d levels", path,
                            line, column, CJSON_NESTING_LIMIT);
        if (at >= size)
            return sam_fail(err, SAM_ERR_FORMAT, "%s:%zu:%zu: JSON ends early (truncated?)", path,
                            line, column);
        char near[SHOWN_SIZE];
        return sam_fail(err, SAM_ERR_FORMAT, "%s:%zu:%zu: JSON syntax error near '%s'", path, line,
                        column, shown(text + at, 16, near));
    }
    sam_status s = SAM_OK;
    const cJSON *found[KEY_COUNT];
    if (!cJSON_IsObject(root)) {
        s = sam_fail(err, SAM_ERR_FORMAT, "%s: expected a JSON object at the top level, found %s",
                     path, sam_json_kind(root));
        goto done;
    }
    s = json_members(&ctx, root, "", keys, KEY_COUNT, found);
    if (s != SAM_OK)
        goto done;
    if (found[KEY_TYPE] && found[KEY_KIND]) {
        s = sam_fail(err, SAM_ERR_FORMAT, "%s: both \"type\" and \"kind\" given; use one", path);
        goto done;
    }
    const cJSON *type = found[KEY_TYPE] ? found[KEY_TYPE] : found[KEY_KIND];
    const char *type_key = found[KEY_TYPE] ? "type" : "kind";
    if (!type) {
        s = sam_fail(err, SAM_ERR_FORMAT,
                     "%s: missing key \"type\" (\"gaussians\", \"dipole\", \"burley\" or \"table\")", path);
        goto done;
    }
    if (!cJSON_IsString(type)) {
        s = sam_json_fail(&ctx, SAM_ERR_FORMAT, type_key, "expected a string, found %s", sam_json_kind(type));
        goto done;
    }
    int kind = 0;
    while (kind < TYPE_COUNT && strcmp(type->valuestring, type_names[kind]) != 0)
        kind++;
    if (kind == TYPE_COUNT) {
        char type_shown[SHOWN_SIZE];
        s = sam_json_fail(&ctx, SAM_ERR_FORMAT, type_key,
                          "\"%s\" is not a profile type (\"gaussians\", \"dipole\", \"burley\" or \"table\")",
                          shown(type->valuestring, 64, type_shown));
        goto done;
    }
    /* Keys of another type would be silently ignored: refuse them. */
    for (int key = KEY_GAUSSIANS; key < KEY_COUNT; key++) {
        if (found[key] && !(type_keys[kind] >> key & 1u)) {
            s = sam_json_fail(&ctx, SAM_ERR_FORMAT, keys[key], "not allowed in a \"%s\" profile", type_names[kind]);
            goto done;
        }
        if (!found[key] && (type_required[kind] >> key & 1u)) {
            s = sam_fail(err, SAM_ERR_FORMAT, "%s: missing key \"%s\" of a %s profile", path, keys[key],
                         type_names[kind]);
            goto done;
        }
    }
    if (kind == TYPE_BURLEY && !found[KEY_MFP] == !found[KEY_RADIUS]) {
        s = sam_fail(err, SAM_ERR_FORMAT, "%s: a burley profile takes one of \"mean_free_path\" and \"scatter_radius\", "
                     "found %s", path, found[KEY_MFP] ? "both" : "neither");
        goto done;
    }
    char name[SAM_PROFILE_NAME_SIZE];
    default_name(path, name);
    if (found[KEY_NAME]) {
        const cJSON *n = found[KEY_NAME];
        if (!cJSON_IsString(n)) {
            s = sam_json_fail(&ctx, SAM_ERR_FORMAT, "name", "expected a string, found %s", sam_json_kind(n));
            goto done;
        }
        size_t len = strlen(n->valuestring);
        if (len < 1 || len > SAM_PROFILE_NAME_SIZE - 1) {
            s = sam_json_fail(&ctx, SAM_ERR_FORMAT, "name", "%zu bytes long, expected 1..%d", len,
                              SAM_PROFILE_NAME_SIZE - 1);
            goto done;
        }
        replace_name(name, n->valuestring, len);
    }
    if (kind == TYPE_DIPOLE) {
        float ssp[3], sa[3], eta;
        if ((s = sam_json_checked_rgb(&ctx, found[KEY_SSP], "sigma_s_prime", sam_profile_check_sigma_s_prime,
                                      ssp)) != SAM_OK ||
            (s = sam_json_checked_rgb(&ctx, found[KEY_SA], "sigma_a", sam_profile_check_sigma_a, sa)) != SAM_OK ||
            (s = sam_json_checked_number(&ctx, found[KEY_ETA], "eta", sam_profile_check_eta, &eta)) != SAM_OK)
            goto done;
        sam_error inner;
        if (sam_profile_dipole(ssp, sa, eta, out, &inner) != SAM_OK) {
            s = sam_fail(err, SAM_ERR_FORMAT, "%s: %s", path, inner.message);
            goto done;
        }
    } else if (kind == TYPE_BURLEY) {
        const int mfp = found[KEY_MFP] != NULL;
        float albedo[3], distance[3];
        if ((s = sam_json_checked_rgb(&ctx, found[KEY_ALBEDO], "albedo", sam_profile_check_albedo, albedo)) !=
                SAM_OK ||
            (s = sam_json_checked_rgb(&ctx, found[mfp ? KEY_MFP : KEY_RADIUS], keys[mfp ? KEY_MFP : KEY_RADIUS],
                                      sam_profile_check_variance, distance)) != SAM_OK)
            goto done;
        sam_error inner;
        if (sam_profile_burley(albedo, distance, mfp ? SAM_BURLEY_MEAN_FREE_PATH : SAM_BURLEY_SCATTER_RADIUS, out,
                               &inner) != SAM_OK) {
            s = sam_fail(err, SAM_ERR_FORMAT, "%s: %s", path, inner.message);
            goto done;
        }
    } else if (kind == TYPE_TABLE) {
        if ((s = json_table(&ctx, found[KEY_TABLE_R], found[KEY_TABLE_RD], out)) != SAM_OK)
            goto done;
    } else {
        s = json_gaussians(&ctx, found[KEY_GAUSSIANS], out);
        if (s != SAM_OK)
            goto done;
    }
    memcpy(out->name, name, sizeof name);
done:
    cJSON_Delete(root);
    return s;
}

/* ---------------------------------------------------------------------- */
/* Text                                                                   */

#define MAX_TOKENS 8

typedef struct text_ctx {
    const char *path;
    int line;
    sam_error *err;
} text_ctx;

/* Parses token `tok` as a number for `what` and checks it. */
static sam_status text_number(const text_ctx *ctx, const char *tok, const char *what,
                              const char *(*check)(double), float *out)
{
    char *end = NULL;
    double v = strtod(tok, &end);
    char tok_shown[SHOWN_SIZE];
    if (end == tok || *end)
        return sam_fail(ctx->err, SAM_ERR_FORMAT, "%s:%d: %s: '%s' is not a number", ctx->path,
                        ctx->line, what, shown(tok, 40, tok_shown));
    const char *why = check(v);
    if (why)
        return sam_fail(ctx->err, SAM_ERR_FORMAT, "%s:%d: %s: %s %s", ctx->path, ctx->line, what,
                        shown(tok, 40, tok_shown), why);
    *out = (float)v;
    return SAM_OK;
}

static sam_status expect_args(const text_ctx *ctx, char **tok, int ntok, int want)
{
    if (ntok - 1 == want)
        return SAM_OK;
    return sam_fail(ctx->err, SAM_ERR_FORMAT, "%s:%d: '%s' takes %d value%s, found %d%s",
                    ctx->path, ctx->line, tok[0], want, want == 1 ? "" : "s",
                    ntok > MAX_TOKENS + 1 ? MAX_TOKENS : ntok - 1,
                    ntok > MAX_TOKENS + 1 ? " or more" : "");
}

static sam_status text_rgb(const text_ctx *ctx, char **tok, const char *(*check)(double),
                           float out[3])
{
    for (int c = 0; c < 3; c++) {
        char what[64];
        snprintf(what, sizeof what, "%s.%c", tok[0], rgb_names[c]);
        sam_status s = text_number(ctx, tok[1 + c], what, check, &out[c]);
        if (s != SAM_OK)
            return s;
    }
    return SAM_OK;
}

static sam_status load_text(const char *path, char *text, sam_profile *out, sam_error *err)
{
    text_ctx ctx = {path, 0, err};
    float variance[SAM_PROFILE_MAX_GAUSSIANS], weight[SAM_PROFILE_MAX_GAUSSIANS][3];
    uint32_t count = 0;
    int dipole_line = 0, ssp_line = 0, sa_line = 0, eta_line = 0, name_line = 0;
    float ssp[3], sa[3], eta = 0;
    char name[SAM_PROFILE_NAME_SIZE];
    default_name(path, name);
    sam_status s;

    for (char *line = text; line;) {
        char *next = strchr(line, '\n');
        if (next)
            *next++ = 0;
        ctx.line++;
        char *hash = strchr(line, '#');
        if (hash)
            *hash = 0;
        char *tok[MAX_TOKENS + 1];
        int ntok = 0;
        for (char *p = line;;) {
            while (*p && isspace((unsigned char)*p))
                p++;
            if (!*p)
                break;
            if (ntok == MAX_TOKENS + 1) {
                ntok++; /* one too many: enough for expect_args' message */
                break;
            }
            tok[ntok++] = p;
            while (*p && !isspace((unsigned char)*p))
                p++;
            if (*p)
                *p++ = 0;
        }
        line = next;
        if (ntok == 0)
            continue;
        const char *kw = tok[0];
        if (strcmp(kw, "gaussian") == 0) {
            if (dipole_line)
                return sam_fail(err, SAM_ERR_FORMAT,
                                "%s:%d: 'gaussian' line in the dipole profile begun on line %d",
                                path, ctx.line, dipole_line);
            if (count == SAM_PROFILE_MAX_GAUSSIANS)
                return sam_fail(err, SAM_ERR_FORMAT, "%s:%d: too many gaussians (at most %d)",
                                path, ctx.line, SAM_PROFILE_MAX_GAUSSIANS);
            if ((s = expect_args(&ctx, tok, ntok, 4)) != SAM_OK ||
                (s = text_number(&ctx, tok[1], "gaussian variance", sam_profile_check_variance,
                                 &variance[count])) != SAM_OK)
                return s;
            for (int c = 0; c < 3; c++) {
                char what[32];
                snprintf(what, sizeof what, "gaussian weight.%c", rgb_names[c]);
                if ((s = text_number(&ctx, tok[2 + c], what, sam_profile_check_weight,
                                     &weight[count][c])) != SAM_OK)
                    return s;
            }
            count++;
        } else if (strcmp(kw, "dipole") == 0) {
            if (count)
                return sam_fail(err, SAM_ERR_FORMAT,
                                "%s:%d: 'dipole' in a file that already has gaussian lines", path,
                                ctx.line);
            if (dipole_line)
                return sam_fail(err, SAM_ERR_FORMAT, "%s:%d: second 'dipole' (first on line %d)",
                                path, ctx.line, dipole_line);
            if ((s = expect_args(&ctx, tok, ntok, 0)) != SAM_OK)
                return s;
            dipole_line = ctx.line;
        } else if (strcmp(kw, "sigma_s_prime") == 0 || strcmp(kw, "sigma_a") == 0 ||
                   strcmp(kw, "eta") == 0) {
            int is_eta = kw[0] == 'e', is_sa = strcmp(kw, "sigma_a") == 0;
            int *seen = is_eta ? &eta_line : (is_sa ? &sa_line : &ssp_line);
            if (!dipole_line)
                return sam_fail(err, SAM_ERR_FORMAT,
                                "%s:%d: '%s' outside a dipole block (put 'dipole' first)", path,
                                ctx.line, kw);
            if (*seen)
                return sam_fail(err, SAM_ERR_FORMAT, "%s:%d: second '%s' (first on line %d)",
                                path, ctx.line, kw, *seen);
            if ((s = expect_args(&ctx, tok, ntok, is_eta ? 1 : 3)) != SAM_OK)
                return s;
            if (is_eta)
                s = text_number(&ctx, tok[1], "eta", sam_profile_check_eta, &eta);
            else if (is_sa)
                s = text_rgb(&ctx, tok, sam_profile_check_sigma_a, sa);
            else
                s = text_rgb(&ctx, tok, sam_profile_check_sigma_s_prime, ssp);
            if (s != SAM_OK)
                return s;
            *seen = ctx.line;
        } else if (strcmp(kw, "name") == 0) {
            if (name_line)
                return sam_fail(err, SAM_ERR_FORMAT, "%s:%d: second 'name' (first on line %d)",
                                path, ctx.line, name_line);
            if ((s = expect_args(&ctx, tok, ntok, 1)) != SAM_OK)
                return s;
            size_t len = strlen(tok[1]);
            if (len > SAM_PROFILE_NAME_SIZE - 1)
                return sam_fail(err, SAM_ERR_FORMAT, "%s:%d: name is %zu bytes long, at most %d",
                                path, ctx.line, len, SAM_PROFILE_NAME_SIZE - 1);
            replace_name(name, tok[1], len);
            name_line = ctx.line;
        } else {
            char kw_shown[SHOWN_SIZE];
            return sam_fail(err, SAM_ERR_FORMAT,
                            "%s:%d: unknown keyword '%s' (expected gaussian, dipole, "
                            "sigma_s_prime, sigma_a, eta or name)",
                            path, ctx.line, shown(kw, 40, kw_shown));
        }
    }

    sam_error inner;
    if (dipole_line) {
        const char *missing = !ssp_line ? "sigma_s_prime" : (!sa_line ? "sigma_a" : "eta");
        if (!ssp_line || !sa_line || !eta_line)
            return sam_fail(err, SAM_ERR_FORMAT, "%s: the dipole on line %d has no '%s' line",
                            path, dipole_line, missing);
        if (sam_profile_dipole(ssp, sa, eta, out, &inner) != SAM_OK)
            return sam_fail(err, SAM_ERR_FORMAT, "%s: %s", path, inner.message);
    } else if (count) {
        const float(*w)[3] = weight;
        if (sam_profile_gaussian_sum(count, variance, w, out, &inner) != SAM_OK)
            return sam_fail(err, SAM_ERR_FORMAT, "%s: %s", path, inner.message);
    } else {
        return sam_fail(err, SAM_ERR_FORMAT,
                        "%s: no profile: expected 'gaussian' lines or a 'dipole' block", path);
    }
    memcpy(out->name, name, sizeof name);
    return SAM_OK;
}

sam_status sam_profile_parse_json(const char *text, size_t size, const char *name, sam_profile *out,
                                  sam_error *err)
{
    if (!text || !out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_profile_parse_json: NULL argument");
    /* load_json expects the NUL sam_read_file appends after the text. */
    char *copy = malloc(size + 1);
    if (!copy)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory", name ? name : "profile");
    memcpy(copy, text, size);
    copy[size] = 0;
    sam_profile parsed;
    sam_status s = load_json(name ? name : "profile", copy, size, &parsed, err);
    free(copy);
    if (s == SAM_OK)
        *out = parsed;
    return s;
}

sam_status sam_profile_load(const char *path, sam_profile *out, sam_error *err)
{
    if (!path || !out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_profile_load: NULL argument");
    uint8_t *data;
    size_t size;
    sam_status s = sam_read_file(path, &data, &size, err);
    if (s != SAM_OK)
        return s;
    char *text = (char *)data;
    const char *nul = memchr(text, 0, size);
    size_t first = 0;
    while (first < size && isspace((unsigned char)text[first]))
        first++;
    sam_profile parsed;
    if (nul)
        s = sam_fail(err, SAM_ERR_FORMAT, "%s: NUL byte at offset %zu (not a text file)", path,
                     (size_t)(nul - text));
    else if (first == size)
        s = sam_fail(err, SAM_ERR_FORMAT, "%s: empty file", path);
    else if (sam_path_has_extension(path, ".json") || text[first] == '{')
        s = load_json(path, text, size, &parsed, err);
    else
        s = load_text(path, text, &parsed, err);
    free(data);
    if (s == SAM_OK)
        *out = parsed;
    return s;
}

/* Here rather than beside the presets so that the loader calls the
 * constructors and nothing calls back into the loader. */
sam_status sam_profile_from_spec(const char *spec, sam_profile *out, sam_error *err)
{
    if (!spec || !out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_profile_from_spec: NULL argument");
    /* A preset's name wins: a file named like one needs a path ("./skin"). */
    if (sam_profile_preset(spec, out, NULL) == SAM_OK)
        return SAM_OK;
    sam_error load_err;
    sam_status s = sam_profile_load(spec, out, &load_err);
    if (s == SAM_ERR_IO) {
        /* Say both readings failed: a mistyped preset looks like a path. */
        char names[256] = "";
        for (size_t i = 0, used = 0; i < sam_profile_preset_count() && used < sizeof names; ++i) {
            const int w = snprintf(names + used, sizeof names - used, "%s%s", i ? ", " : "", sam_profile_preset_name(i));
            used += w > 0 ? (size_t)w : 0;
        }
        return sam_fail(err, s, "'%s' is neither a preset (%s) nor a profile file that can be read (%s)", spec, names,
                        load_err.message);
    }
    if (s != SAM_OK && err)
        *err = load_err;
    return s;
}
