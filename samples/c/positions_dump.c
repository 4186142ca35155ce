#include "positions_dump.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int positions_dump_write(const char* path, const float* values, size_t count, char* err, size_t err_size) {
  const size_t plen = strlen(path);
  char* partial = (char*)malloc(plen + sizeof ".partial");
  unsigned char bytes[4096];
  size_t i, fill = 0;
  int ok = 1;
  FILE* f;
  if (!partial) {
    snprintf(err, err_size, "out of memory");
    return -1;
  }
  memcpy(partial, path, plen);
  memcpy(partial + plen, ".partial", sizeof ".partial");
  if (!(f = fopen(partial, "wb"))) {
    snprintf(err, err_size, "cannot create %s: %s", partial, strerror(errno));
    free(partial);
    return -1;
  }
  /* Byte by byte from the bit pattern, so the file is little-endian on any
   * machine. */
  for (i = 0; i < count && ok; ++i) {
    uint32_t u;
    memcpy(&u, &values[i], sizeof u);
    bytes[fill++] = (unsigned char)(u & 0xFF);
    bytes[fill++] = (unsigned char)((u >> 8) & 0xFF);
    bytes[fill++] = (unsigned char)((u >> 16) & 0xFF);
    bytes[fill++] = (unsigned char)((u >> 24) & 0xFF);
    if (fill == sizeof bytes || i + 1 == count) {
      ok = fwrite(bytes, 1, fill, f) == fill;
      fill = 0;
    }
  }
  if (fclose(f) != 0) ok = 0;
  if (!ok) {
    snprintf(err, err_size, "cannot write %s", partial);
    remove(partial);
    free(partial);
    return -1;
  }
  if (rename(partial, path) != 0) {
    snprintf(err, err_size, "cannot rename %s to %s: %s", partial, path, strerror(errno));
    remove(partial);
    free(partial);
    return -1;
  }
  free(partial);
  return 0;
}
