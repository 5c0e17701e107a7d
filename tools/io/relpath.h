/*
 * io/relpath.h - a file named inside another file (a glTF buffer or image uri, an OBJ mtllib or
 * map_Kd) resolved against that file's folder, refusing names that would leave it. Hosted.
 *
 * Refused: an empty name, an absolute path ("/..."), a ".." component anywhere, a backslash, a
 * control character (messages stay one line) and a URI scheme ("http:", "file:"): a downloaded scene must not make the tools read files outside
 * its own folder (a texture could carry ~/.ssh/id_rsa into a baked asset). Symbolic links inside
 * the folder are followed as the file system does.
 */
#ifndef QTOOL_IO_RELPATH_H
#define QTOOL_IO_RELPATH_H

#include <stddef.h>

/* dir + "/" + rel into out (cap bytes). 0, or -1 with *why a short static reason ("an absolute
 * path", "a '..'", "a backslash", "a control character", "a URI scheme", "empty", "too long"). */
int qtool_io_relpath(const char *dir, const char *rel, char *out, size_t cap, const char **why);

/* The folder of path ("." for a bare name) into out; 0, or -1 if it does not fit. */
int qtool_io_dirname(const char *path, char *out, size_t cap);

#endif
