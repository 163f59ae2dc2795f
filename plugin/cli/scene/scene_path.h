/* File names of a scene: copies, and paths relative to the scene file's folder. */
#ifndef WEFT_CLI_SCENE_PATH_H
#define WEFT_CLI_SCENE_PATH_H

/* A copy of s (NULL when out of memory). */
char* scene_strdup(const char* s);
/* name's folder joined with file, or file itself when absolute or name has no folder (allocated;
 * NULL when out of memory). */
char* scene_resolve_path(const char* name, const char* file);

#endif
