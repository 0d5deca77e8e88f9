/* The build's progress display on stderr and its cancel signals (sam_app.h). */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "sam/sam_app.h"

void sam_app_progress_init(sam_app_progress *bar, const char *tool, int quiet, volatile sig_atomic_t *cancel)
{
    bar->tool = tool;
    bar->start = sam_seconds();
    bar->tty = isatty(2);
    bar->quiet = quiet;
    bar->last_decile = 0;
    bar->open_line = 0;
    bar->cancel = cancel;
}

int sam_app_progress_update(void *user, uint64_t done, uint64_t total)
{
    sam_app_progress *v = user;
    if (v->cancel && *v->cancel)
        return 1;
    if (v->quiet || total == 0)
        return 0;
    double elapsed = sam_seconds() - v->start, frac = (double)done / (double)total;
    double eta = frac > 0 ? elapsed * (1 - frac) / frac : 0;
    if (v->tty) {
        char bar[41];
        int fill = (int)(frac * 40);
        for (int i = 0; i < 40; ++i)
            bar[i] = i < fill ? '=' : (i == fill ? '>' : ' ');
        bar[40] = 0;
        fprintf(stderr, "\r[%s] %3d%% %llu/%llu vertices, %.1f s, ETA %.1f s   ", bar, (int)(frac * 100),
                (unsigned long long)done, (unsigned long long)total, elapsed, eta);
        v->open_line = done != total;
        if (done == total)
            fputc('\n', stderr);
    } else if ((int)(frac * 10) > v->last_decile) {
        /* Logs get a line per 10%, not a carriage-return bar. */
        v->last_decile = (int)(frac * 10);
        fprintf(stderr, "%s: %3d%% (%llu/%llu vertices), %.1f s, ETA %.1f s\n", v->tool, v->last_decile * 10,
                (unsigned long long)done, (unsigned long long)total, elapsed, eta);
    }
    return 0;
}

void sam_app_catch_interrupts(void (*handler)(int))
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = handler ? handler : SIG_DFL;
    sa.sa_flags = handler ? SA_RESETHAND : 0;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}
