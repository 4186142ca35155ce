/* Raw dump of played surfaces: little-endian float32, frames x vertices x 3
 * (cm), nothing else. The C#, Rust and C samples all write it, and the test
 * samples_agree compares their files. */
#ifndef FACESR_SAMPLE_POSITIONS_DUMP_H
#define FACESR_SAMPLE_POSITIONS_DUMP_H

#include <stddef.h>

/* Writes count floats to path (via path.partial, renamed when complete).
 * 0 on success; otherwise -1 with the problem in err and no file left. */
int positions_dump_write(const char* path, const float* values, size_t count, char* err, size_t err_size);

#endif
