/* Private file-system helpers (fsutil.c), shared by checkpoint.c and results.c. */
#ifndef FPUTLAB_FSUTIL_H
#define FPUTLAB_FSUTIL_H

#include <stddef.h>

/* fsync of a file or folder by name: 0, or -1 with errno. */
int fpl_fsync_path(const char *path);
/* The folder part of a path ("." for a bare name, "/" for the root). */
void fpl_folder_of(const char *path, char *dir, size_t len);
/* The file a path finally names, symbolic links followed (also a dangling last one), so that a
 * rename onto it keeps the links. 0, or -1 with errno. */
int fpl_resolve_target(const char *path, char *out, size_t len);
/* Remove temporaries "<path><tag>PID" left by processes that no longer exist. */
void fpl_remove_stale_temporaries(const char *path, const char *tag);

#endif
