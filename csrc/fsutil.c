/* File-system helpers of the files the library writes (checkpoints, results files): fsync by
 * name, the folder of a path, the final target of a symbolic link, stale temporaries of dead
 * processes. Their own file, so that checkpoint.c and results.c share them without including
 * each other's declarations. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>
#include "fsutil.h"

static int fsync_path(const char *path, int flags)
{
    int fd = open(path, flags);
    if (fd < 0) return -1;
    int rc = fsync(fd);
    close(fd);
    return rc;
}

void fpl_folder_of(const char *path, char *dir, size_t len)
{
    const char *slash = strrchr(path, '/');
    if (!slash) snprintf(dir, len, ".");
    else if (slash == path) snprintf(dir, len, "/");
    else snprintf(dir, len, "%.*s", (int)(slash - path), path);
}

int fpl_fsync_path(const char *path) { return fsync_path(path, O_RDONLY); }

/* Where a checkpoint really goes: a symbolic link is followed (also a dangling one), so that the
 * link stays a link and its target receives the new checkpoint. */
int fpl_resolve_target(const char *path, char *out, size_t len)
{
    char cur[4096], link[4096];
    if (snprintf(cur, sizeof cur, "%s", path) >= (int)sizeof cur) return -1;
    for (int depth = 0; depth < 40; depth++) {
        struct stat sb;
        if (lstat(cur, &sb) != 0 || !S_ISLNK(sb.st_mode)) {
            return snprintf(out, len, "%s", cur) >= (int)len ? -1 : 0;
        }
        ssize_t n = readlink(cur, link, sizeof link - 1);
        if (n < 0) return -1;
        link[n] = '\0';
        if (link[0] == '/') {
            memcpy(cur, link, (size_t)n + 1);
        } else {
            char dir[4096];
            fpl_folder_of(cur, dir, sizeof dir);
            char next[8192];
            snprintf(next, sizeof next, "%s/%s", dir, link);
            if (strlen(next) >= sizeof cur) return -1;
            memcpy(cur, next, strlen(next) + 1);
        }
    }
    errno = ELOOP;
    return -1;
}

/* Remove temporary files "<path><tag>PID" left by processes that no longer exist (killed while
 * writing a checkpoint, or while resuming a results file). */
void fpl_remove_stale_temporaries(const char *path, const char *tag)
{
    char dir[4096];
    fpl_folder_of(path, dir, sizeof dir);
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    char prefix[4096];
    if (snprintf(prefix, sizeof prefix, "%s%s", base, tag) >= (int)sizeof prefix) return;
    size_t np = strlen(prefix);
    DIR *d = opendir(dir);
    if (!d) return;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (strncmp(e->d_name, prefix, np) != 0) continue;
        char *end;
        errno = 0;
        long pid = strtol(e->d_name + np, &end, 10);
        if (errno || *end || end == e->d_name + np || pid <= 0 || pid > INT_MAX) continue;
        if (pid == (long)getpid()) continue;
        if (kill((pid_t)pid, 0) == 0 || errno != ESRCH) continue;   /* alive, or not ours */
        char full[8192];
        snprintf(full, sizeof full, "%s/%s", dir, e->d_name);
        remove(full);
    }
    closedir(d);
}
