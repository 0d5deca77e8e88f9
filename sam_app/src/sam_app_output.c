/* Outputs checked before any work (sam_app_output.h). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "sam/sam_app_output.h"

int sam_app_has_extension(const char *path, const char *extension)
{
    size_t n = strlen(path), m = strlen(extension);
    return n > m && !strcasecmp(path + n - m, extension);
}

sam_status sam_app_check_output(const char *what, const char *path, const char *const *extensions, int force,
                                sam_error *err)
{
    if (!path || !path[0])
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: no file name given", what);
    struct stat st;
    if (stat(path, &st) == 0) {
        if (S_ISDIR(st.st_mode))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s %s is a folder, not a file name", what, path);
        if (!S_ISREG(st.st_mode))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s %s exists and is not a regular file", what, path);
        if (!force)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s %s exists (--force replaces it)", what, path);
    }
    char dir[4096];
    const char *slash = strrchr(path, '/');
    if (!slash)
        snprintf(dir, sizeof dir, ".");
    else if (slash == path)
        snprintf(dir, sizeof dir, "/");
    else
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    if (stat(dir, &st) != 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s %s: the folder %s does not exist", what, path, dir);
    if (!S_ISDIR(st.st_mode))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s %s: %s is not a folder", what, path, dir);
    /* Not access(): it answers for the permission bits only, and root
     * passes it on folders that still refuse a new file (sysfs, proc, some
     * network and read-only-remounted disks). Creating one is the question
     * asked, and its errno says why not as access() did. */
    char probe[4200];
    snprintf(probe, sizeof probe, "%s/.sam_write_probe_XXXXXX", dir);
    int fd = mkstemp(probe);
    if (fd < 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s %s: cannot write in %s (%s)", what, path, dir,
                        strerror(errno));
    close(fd);
    unlink(probe);
    if (extensions) {
        int known = 0;
        char list[128] = "";
        for (const char *const *e = extensions; *e; ++e) {
            known |= sam_app_has_extension(path, *e);
            snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", list[0] ? " or " : "", *e);
        }
        if (!known)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s %s: the name must end in %s", what, path, list);
    }
    return SAM_OK;
}
