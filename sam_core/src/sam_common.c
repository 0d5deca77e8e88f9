#define _POSIX_C_SOURCE 200809L
#include "sam/sam_common.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

const char *sam_status_name(sam_status status)
{
    switch (status) {
    case SAM_OK: return "ok";
    case SAM_ERR_INVALID_ARGUMENT: return "invalid argument";
    case SAM_ERR_IO: return "i/o error";
    case SAM_ERR_FORMAT: return "format error";
    case SAM_ERR_CORRUPT: return "corrupt data";
    case SAM_ERR_UNSUPPORTED: return "unsupported";
    case SAM_ERR_OUT_OF_MEMORY: return "out of memory";
    case SAM_ERR_EMPTY: return "empty input";
    }
    return "unknown status";
}

sam_status sam_fail(sam_error *err, sam_status status, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
        err->status = status;
    }
    return status;
}

void sam_error_clear(sam_error *err)
{
    if (err) {
        err->status = SAM_OK;
        err->message[0] = '\0';
    }
}

char *sam_strdup(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d)
        memcpy(d, s, n);
    return d;
}

void sam_text_append(sam_text *t, const char *s, size_t n)
{
    if (t->oom)
        return;
    if (n > SIZE_MAX / 2 - 1 - t->len) {
        t->oom = 1;
        return;
    }
    if (t->len + n + 1 > t->cap) {
        size_t cap = t->cap ? t->cap * 2 : 4096;
        while (cap < t->len + n + 1)
            cap *= 2;
        char *p = realloc(t->p, cap);
        if (!p) {
            t->oom = 1;
            return;
        }
        t->p = p;
        t->cap = cap;
    }
    if (n)
        memcpy(t->p + t->len, s, n);
    t->len += n;
    t->p[t->len] = '\0';
}

int sam_parse_double(const char *text, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(text, &end);
    if (!text[0] || *end || errno || !isfinite(v))
        return 0;
    *out = v;
    return 1;
}

/* Removes "PATH.tmp.PID.N" files that a killed writer (no process PID is
 * alive) left beside PATH, so they cannot pile up; a live writer's, and
 * anything not named so, stay. Best effort: what cannot be read or
 * removed is left. */
static void remove_stale_temporaries(const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const size_t dir_len = slash ? (size_t)(slash - path) : 0, base_len = strlen(base);
    char *dir = malloc(dir_len + 2), *stale = malloc(strlen(path) + 64);
    if (!dir || !stale) {
        free(dir);
        free(stale);
        return;
    }
    if (slash)
        memcpy(dir, path, dir_len ? dir_len : 1), dir[dir_len ? dir_len : 1] = 0;
    else
        strcpy(dir, ".");
    DIR *d = opendir(dir);
    for (struct dirent *e; d && (e = readdir(d)) != NULL;) {
        const char *name = e->d_name;
        if (strncmp(name, base, base_len) != 0 || strncmp(name + base_len, ".tmp.", 5) != 0)
            continue;
        char *end;
        errno = 0;
        const long pid = strtol(name + base_len + 5, &end, 10);
        if (errno || end == name + base_len + 5 || *end != '.' || pid <= 0 || pid == (long)getpid())
            continue;
        const char *counter = end + 1;
        strtoul(counter, &end, 10);
        if (end == counter || *end)
            continue;
        if (kill((pid_t)pid, 0) == 0 || errno != ESRCH)
            continue;
        snprintf(stale, strlen(path) + 64, "%s/%s", dir, name);
        remove(stale);
    }
    if (d)
        closedir(d);
    free(dir);
    free(stale);
}

sam_status sam_atomic_open(sam_atomic_file *file, const char *path, sam_error *err)
{
    if (!file || !path || !path[0])
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "atomic write: no output path given");
    memset(file, 0, sizeof *file);
    size_t n = strlen(path) + 64;
    file->path = sam_strdup(path);
    file->temp_path = malloc(n);
    if (!file->path || !file->temp_path) {
        sam_atomic_abort(file);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    remove_stale_temporaries(path);
    /* The counter keeps two writers in one process from sharing a name. */
    static _Thread_local unsigned counter;
    for (int attempt = 0; attempt < 100; ++attempt) {
        snprintf(file->temp_path, n, "%s.tmp.%ld.%u", path, (long)getpid(), counter++);
        /* "x" refuses to reuse an existing file, so a stale temp is never clobbered. */
        file->fp = fopen(file->temp_path, "wbx");
        if (file->fp)
            return SAM_OK;
        if (errno != EEXIST)
            break;
    }
    int e = errno;
    sam_status st = sam_fail(err, SAM_ERR_IO, "%s: cannot create temporary file %s: %s", path,
                             file->temp_path, strerror(e));
    sam_atomic_abort(file);
    return st;
}

sam_status sam_atomic_commit(sam_atomic_file *file, sam_error *err)
{
    if (!file || !file->fp)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "atomic write: file is not open");
    int failed = 0, e = 0;
    const char *what = "";
    if (fflush(file->fp) != 0 || ferror(file->fp)) {
        failed = 1, e = errno, what = "write";
    } else if (fsync(fileno(file->fp)) != 0 && errno != EINVAL) {
        failed = 1, e = errno, what = "fsync";
    }
    if (fclose(file->fp) != 0 && !failed)
        failed = 1, e = errno, what = "close";
    file->fp = NULL;
    if (!failed && rename(file->temp_path, file->path) != 0)
        failed = 1, e = errno, what = "rename";
    sam_status st = SAM_OK;
    if (failed) {
        st = sam_fail(err, SAM_ERR_IO, "%s: %s of %s failed: %s", file->path, what,
                      file->temp_path, strerror(e));
        remove(file->temp_path);
    }
    free(file->path);
    free(file->temp_path);
    memset(file, 0, sizeof *file);
    return st;
}

void sam_atomic_abort(sam_atomic_file *file)
{
    if (!file)
        return;
    if (file->fp) {
        fclose(file->fp);
        remove(file->temp_path);
    }
    free(file->path);
    free(file->temp_path);
    memset(file, 0, sizeof *file);
}

static const char *file_kind(mode_t mode)
{
    return S_ISDIR(mode)    ? "a directory"
           : S_ISCHR(mode)  ? "a character device"
           : S_ISBLK(mode)  ? "a block device"
           : S_ISFIFO(mode) ? "a pipe"
           : S_ISSOCK(mode) ? "a socket"
                            : "not a file";
}

sam_status sam_check_regular_file(const char *path, sam_error *err)
{
    struct stat st;
    if (!path)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "check file: NULL path");
    if (stat(path, &st) != 0)
        return sam_fail(err, SAM_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    if (!S_ISREG(st.st_mode))
        return sam_fail(err, SAM_ERR_IO, "%s: not a regular file (%s)", path, file_kind(st.st_mode));
    return SAM_OK;
}

sam_status sam_read_file(const char *path, uint8_t **data, size_t *size, sam_error *err)
{
    if (!path || !data || !size)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "read file: NULL argument");
    *data = NULL;
    *size = 0;
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return sam_fail(err, SAM_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    /* What was opened, not what the path names now, must be a file. */
    struct stat st;
    if (fstat(fileno(fp), &st) != 0) {
        int e = errno;
        fclose(fp);
        return sam_fail(err, SAM_ERR_IO, "%s: cannot examine: %s", path, strerror(e));
    }
    if (!S_ISREG(st.st_mode)) {
        fclose(fp);
        return sam_fail(err, SAM_ERR_IO, "%s: not a regular file (%s)", path, file_kind(st.st_mode));
    }
    size_t cap = 1 << 16, len = 0;
    uint8_t *buf = malloc(cap + 1);
    if (!buf) {
        fclose(fp);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    for (;;) {
        size_t got = fread(buf + len, 1, cap - len, fp);
        len += got;
        if (len < cap) {
            if (ferror(fp)) {
                int e = errno;
                free(buf);
                fclose(fp);
                return sam_fail(err, SAM_ERR_IO, "%s: read failed after %zu bytes: %s", path, len,
                                strerror(e));
            }
            break;
        }
        uint8_t *grown = realloc(buf, cap * 2 + 1);
        if (!grown) {
            free(buf);
            fclose(fp);
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory after %zu bytes", path,
                            len);
        }
        buf = grown;
        cap *= 2;
    }
    fclose(fp);
    buf[len] = 0;
    *data = buf;
    *size = len;
    return SAM_OK;
}

const char *sam_path_basename(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

int sam_path_has_extension(const char *path, const char *suffix)
{
    size_t n = strlen(path), m = strlen(suffix);
    return n >= m && strcasecmp(path + n - m, suffix) == 0;
}

double sam_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
