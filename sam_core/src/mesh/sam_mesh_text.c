/* Counts, numbers and text checks for the mesh pre-check (sam_mesh_text.h). */
#include "sam_mesh_text.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <strings.h>

/* A decimal number as C++ stream extraction reads one, which OpenMesh
 * uses: [+-]digits[.digits][(e|E)[+-]digits], a digit before or after the
 * point. strtod also takes hex ("0xce"), "inf" and "nan", on which the
 * stream stops and OpenMesh drops the line. */
static int decimal_syntax(const char *tok, int len)
{
    int i = 0, digits = 0;
    if (i < len && (tok[i] == '+' || tok[i] == '-'))
        i++;
    while (i < len && isdigit((unsigned char)tok[i]))
        i++, digits++;
    if (i < len && tok[i] == '.')
        for (i++; i < len && isdigit((unsigned char)tok[i]); i++)
            digits++;
    if (!digits)
        return 0;
    if (i < len && (tok[i] == 'e' || tok[i] == 'E')) {
        int exponent = 0;
        if (++i < len && (tok[i] == '+' || tok[i] == '-'))
            i++;
        while (i < len && isdigit((unsigned char)tok[i]))
            i++, exponent++;
        if (!exponent)
            return 0;
    }
    return i == len;
}

/* A whole token read as a number: 1 when it is a decimal number that fits
 * a 32-bit float (finite, at most FLT_MAX in size; smaller ones round to 0
 * or a subnormal, as a float reader gives them), -1 when it is a number
 * that does not, 0 when it is no decimal number. */
int sam_mesh_token_number(const char *tok, int len)
{
    char buf[64];
    if (len <= 0 || len >= (int)sizeof buf)
        return 0;
    if (!decimal_syntax(tok, len)) {
        /* "inf" and "nan" are numbers, just not finite ones. */
        const int special = (len >= 3 && (!strncasecmp(tok + (tok[0] == '-' || tok[0] == '+'), "inf", 3) ||
                                          !strncasecmp(tok + (tok[0] == '-' || tok[0] == '+'), "nan", 3)));
        return special ? -1 : 0;
    }
    memcpy(buf, tok, (size_t)len);
    buf[len] = 0;
    char *stop;
    double v = strtod(buf, &stop);
    if (stop == buf || *stop)
        return 0;
    return isfinite(v) && fabs(v) <= FLT_MAX ? 1 : -1;
}

/* Text formats hold printable characters, blanks and line ends (LF or
 * CRLF; and UTF-8 in comments); a control character means a damaged or
 * binary file, on which OpenMesh's stream parsing and ours would disagree
 * (a lone CR in a PLY header sent OpenMesh into an endless loop). */
sam_status sam_mesh_check_text(const char *path, const char *kind, const char *data, size_t size, sam_error *err)
{
    int line = 1;
    for (size_t i = 0; i < size; ++i) {
        unsigned char ch = (unsigned char)data[i];
        if (ch == '\n')
            line++;
        else if ((ch < 0x20 && ch != '\t' && !(ch == '\r' && i + 1 < size && data[i + 1] == '\n')) || ch == 0x7f)
            return sam_fail(err, SAM_ERR_FORMAT, "%s: %s line %d contains the control character 0x%02x", path, kind,
                            line, ch);
    }
    return SAM_OK;
}

