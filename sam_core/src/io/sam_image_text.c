/* Text in float images (sam_image_draw_text in sam_image.h), with
 * stb_easy_font's segment font: every glyph is a handful of axis-aligned
 * quads, so drawing is filling rectangles, with no font file to find. */
#include <stdlib.h>
#include <string.h>

#include <stb_easy_font.h>

#include "sam/sam_image.h"

/* stb_easy_font's vertex: x, y, z floats and 4 colour bytes. */
typedef struct font_vertex {
    float x, y, z;
    unsigned char rgba[4];
} font_vertex;

static char *copy_text(const char *text)
{
    size_t n = strlen(text);
    char *copy = malloc(n + 1);
    if (copy)
        memcpy(copy, text, n + 1);
    return copy;
}

int sam_image_text_width(const char *text, int scale)
{
    char *copy = text ? copy_text(text) : NULL;
    int w = copy ? stb_easy_font_width(copy) * (scale > 0 ? scale : 1) : 0;
    free(copy);
    return w;
}

int sam_image_draw_text(sam_image *img, int x, int y, int scale, const float rgb[3], const char *text)
{
    if (!img || !img->pixels || img->channels < 3 || !rgb || !text)
        return 0;
    scale = scale > 0 ? scale : 1;
    char *copy = copy_text(text);
    /* At most 4 quads of 4 vertices per segment, about 20 segments a glyph. */
    const size_t capacity = (strlen(text) + 1) * 80;
    font_vertex *v = malloc(capacity * sizeof *v);
    if (!copy || !v) {
        free(copy);
        free(v);
        return 0;
    }
    unsigned char white[4] = {255, 255, 255, 255};
    const int quads = stb_easy_font_print(0, 0, copy, white, v, (int)(capacity * sizeof *v));
    const int width = stb_easy_font_width(copy) * scale;
    for (int q = 0; q < quads; q++) {
        const font_vertex *c = v + 4 * q;
        /* A quad's corners are (x0, y0), (x1, y0), (x1, y1), (x0, y1). */
        const int x0 = x + (int)(c[0].x * (float)scale), y0 = y + (int)(c[0].y * (float)scale);
        const int x1 = x + (int)(c[2].x * (float)scale), y1 = y + (int)(c[2].y * (float)scale);
        for (int py = y0 < 0 ? 0 : y0; py < y1 && py < (int)img->height; py++)
            for (int px = x0 < 0 ? 0 : x0; px < x1 && px < (int)img->width; px++)
                memcpy(img->pixels + ((size_t)py * img->width + (size_t)px) * img->channels, rgb, 3 * sizeof(float));
    }
    free(copy);
    free(v);
    return width;
}
