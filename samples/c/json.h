/* A small JSON reader (RFC 8259) for the sample: enough to read a
 * performance file, strict about syntax, bounded in nesting depth so that a
 * hostile file cannot exhaust the stack. */
#ifndef FACESR_SAMPLE_JSON_H
#define FACESR_SAMPLE_JSON_H

#include <stddef.h>

typedef enum json_type { JSON_NULL, JSON_BOOL, JSON_NUMBER, JSON_STRING, JSON_ARRAY, JSON_OBJECT } json_type;

typedef struct json_value json_value;
struct json_value {
  json_type type;
  int boolean;       /* JSON_BOOL */
  double number;     /* JSON_NUMBER */
  char* string;      /* JSON_STRING: UTF-8, NUL-terminated (an embedded \u0000 ends it early) */
  size_t count;      /* JSON_ARRAY, JSON_OBJECT: number of elements or members */
  json_value* items; /* JSON_ARRAY, JSON_OBJECT: the values */
  char** keys;       /* JSON_OBJECT: the member names, parallel to items */
};

/* Parses `length` bytes of text (a UTF-8 byte order mark is skipped). NULL on
 * failure, with "line L, column C: problem" in err. Free with json_free. */
json_value* json_parse(const char* text, size_t length, char* err, size_t err_size);
void json_free(json_value* v);

/* The member `key` of an object (the last one if repeated), or NULL. */
const json_value* json_get(const json_value* object, const char* key);

/* Reads a whole file into a NUL-terminated buffer (free with free()); NULL if
 * it cannot be read. */
char* json_read_file(const char* path, size_t* length);

#endif
