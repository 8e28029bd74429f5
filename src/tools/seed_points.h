// Seed points for the Voronoi pattern, read from a text file (fracture --seeds).
#pragma once

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <breakables/authoring.h>

/// The most points a seed file may hold: a bound on memory only (the
/// fracture itself takes fewer, and bk_fracture_def_validate says how many).
#define BK_SEED_POINTS_MAX (1u << 24)
/// Seed files larger than this are refused before they are parsed.
#define BK_SEED_FILE_MAX_BYTES ((uint64_t)1 << 28)

/// Parses seed points: one point per line, three numbers "x y z" separated
/// by blanks (spaces, tabs), each a plain finite decimal number (as
/// parse_double reads them: no hex, inf or nan); '#' starts a comment that
/// runs to the end of the line; blank lines, comment lines and CR LF line
/// ends are allowed. A line that does not parse, a number beyond a double
/// and a text without points are refused with one line naming `name` and
/// the line ("seeds.txt:3: expected 3 numbers x y z, found 2"). On success
/// *points (allocated; free() it) holds *count >= 1 points; on failure it is
/// NULL and *count 0. The text need not end in a newline or a NUL.
bool seed_points_parse(const char* text, size_t length, const char* name, bk_vec3** points, uint32_t* count,
                       bk_error* err);
/// Reads a seed file (at most BK_SEED_FILE_MAX_BYTES) and parses it with
/// seed_points_parse, naming it by its path.
bool seed_points_load(const char* path, bk_vec3** points, uint32_t* count, bk_error* err);
