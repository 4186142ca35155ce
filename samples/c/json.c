#include "json.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_DEPTH = 64 };

typedef struct parser {
  const char* p;
  const char* end;
  const char* start;
  char* err;
  size_t err_size;
  int failed;
} parser;

static void fail(parser* ps, const char* what) {
  const char* q;
  int line = 1, column = 1;
  if (ps->failed) return;
  ps->failed = 1;
  for (q = ps->start; q < ps->p && q < ps->end; ++q) {
    if (*q == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  if (ps->err && ps->err_size) snprintf(ps->err, ps->err_size, "line %d, column %d: %s", line, column, what);
}

static void skip_space(parser* ps) {
  while (ps->p < ps->end && (*ps->p == ' ' || *ps->p == '\t' || *ps->p == '\n' || *ps->p == '\r')) ++ps->p;
}

static int literal(parser* ps, const char* word) {
  const size_t n = strlen(word);
  if ((size_t)(ps->end - ps->p) < n || memcmp(ps->p, word, n) != 0) return 0;
  ps->p += n;
  return 1;
}

/* Growable byte buffer for strings. */
typedef struct bytes {
  char* data;
  size_t size, capacity;
} bytes;

static int bytes_push(bytes* b, char c) {
  if (b->size + 1 >= b->capacity) {
    const size_t cap = b->capacity ? 2 * b->capacity : 32;
    char* grown = (char*)realloc(b->data, cap);
    if (!grown) return 0;
    b->data = grown;
    b->capacity = cap;
  }
  b->data[b->size++] = c;
  b->data[b->size] = '\0';
  return 1;
}

static int hex4(parser* ps, unsigned* out) {
  unsigned v = 0;
  int i;
  if (ps->end - ps->p < 4) return 0;
  for (i = 0; i < 4; ++i) {
    const char c = *ps->p++;
    v <<= 4;
    if (c >= '0' && c <= '9')
      v |= (unsigned)(c - '0');
    else if (c >= 'a' && c <= 'f')
      v |= (unsigned)(c - 'a' + 10);
    else if (c >= 'A' && c <= 'F')
      v |= (unsigned)(c - 'A' + 10);
    else
      return 0;
  }
  *out = v;
  return 1;
}

static int push_utf8(bytes* b, unsigned cp) {
  if (cp < 0x80) return bytes_push(b, (char)cp);
  if (cp < 0x800) return bytes_push(b, (char)(0xC0 | (cp >> 6))) && bytes_push(b, (char)(0x80 | (cp & 0x3F)));
  if (cp < 0x10000)
    return bytes_push(b, (char)(0xE0 | (cp >> 12))) && bytes_push(b, (char)(0x80 | ((cp >> 6) & 0x3F))) &&
           bytes_push(b, (char)(0x80 | (cp & 0x3F)));
  return bytes_push(b, (char)(0xF0 | (cp >> 18))) && bytes_push(b, (char)(0x80 | ((cp >> 12) & 0x3F))) &&
         bytes_push(b, (char)(0x80 | ((cp >> 6) & 0x3F))) && bytes_push(b, (char)(0x80 | (cp & 0x3F)));
}

/* After the opening quote; returns a malloc'ed string or NULL. */
static char* parse_string(parser* ps) {
  bytes b = {NULL, 0, 0};
  if (!bytes_push(&b, 'x')) goto oom; /* allocate so that "" is a valid empty string */
  b.size = 0;
  b.data[0] = '\0';
  for (;;) {
    char c;
    if (ps->p >= ps->end) {
      fail(ps, "unterminated string");
      goto fail;
    }
    c = *ps->p++;
    if (c == '"') return b.data;
    if ((unsigned char)c < 0x20) {
      fail(ps, "control character in a string");
      goto fail;
    }
    if (c != '\\') {
      if (!bytes_push(&b, c)) goto oom;
      continue;
    }
    if (ps->p >= ps->end) {
      fail(ps, "unterminated escape");
      goto fail;
    }
    c = *ps->p++;
    switch (c) {
      case '"':
      case '\\':
      case '/':
        if (!bytes_push(&b, c)) goto oom;
        break;
      case 'b':
        if (!bytes_push(&b, '\b')) goto oom;
        break;
      case 'f':
        if (!bytes_push(&b, '\f')) goto oom;
        break;
      case 'n':
        if (!bytes_push(&b, '\n')) goto oom;
        break;
      case 'r':
        if (!bytes_push(&b, '\r')) goto oom;
        break;
      case 't':
        if (!bytes_push(&b, '\t')) goto oom;
        break;
      case 'u': {
        unsigned cp, low;
        if (!hex4(ps, &cp)) {
          fail(ps, "bad \\u escape");
          goto fail;
        }
        if (cp >= 0xD800 && cp <= 0xDBFF) {
          if (!literal(ps, "\\u") || !hex4(ps, &low) || low < 0xDC00 || low > 0xDFFF) {
            fail(ps, "unpaired UTF-16 surrogate in a \\u escape");
            goto fail;
          }
          cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
        } else if (cp >= 0xDC00 && cp <= 0xDFFF) {
          fail(ps, "unpaired UTF-16 surrogate in a \\u escape");
          goto fail;
        }
        if (!push_utf8(&b, cp)) goto oom;
        break;
      }
      default:
        fail(ps, "unknown escape in a string");
        goto fail;
    }
  }
oom:
  fail(ps, "out of memory");
fail:
  free(b.data);
  return NULL;
}

/* JSON number grammar checked by hand: strtod alone would also take "0x1p3",
 * "inf" or "nan". */
static int parse_number(parser* ps, double* out) {
  const char* q = ps->p;
  char buf[64];
  size_t n;
  if (q < ps->end && *q == '-') ++q;
  if (q < ps->end && *q == '0') {
    ++q;
  } else if (q < ps->end && *q >= '1' && *q <= '9') {
    while (q < ps->end && *q >= '0' && *q <= '9') ++q;
  } else {
    return 0;
  }
  if (q < ps->end && *q == '.') {
    ++q;
    if (q >= ps->end || *q < '0' || *q > '9') return 0;
    while (q < ps->end && *q >= '0' && *q <= '9') ++q;
  }
  if (q < ps->end && (*q == 'e' || *q == 'E')) {
    ++q;
    if (q < ps->end && (*q == '+' || *q == '-')) ++q;
    if (q >= ps->end || *q < '0' || *q > '9') return 0;
    while (q < ps->end && *q >= '0' && *q <= '9') ++q;
  }
  n = (size_t)(q - ps->p);
  if (n >= sizeof buf) return 0; /* no real weight or time needs 64 digits */
  memcpy(buf, ps->p, n);
  buf[n] = '\0';
  *out = strtod(buf, NULL);
  ps->p = q;
  return 1;
}

static int parse_value(parser* ps, json_value* v, int depth);

static int push_item(parser* ps, json_value* v, size_t* capacity, char* key) {
  if (v->count == *capacity) {
    const size_t cap = *capacity ? 2 * *capacity : 8;
    json_value* items = (json_value*)realloc(v->items, cap * sizeof *items);
    if (!items) goto oom;
    v->items = items;
    if (v->type == JSON_OBJECT) {
      char** keys = (char**)realloc(v->keys, cap * sizeof *keys);
      if (!keys) goto oom;
      v->keys = keys;
    }
    *capacity = cap;
  }
  memset(&v->items[v->count], 0, sizeof v->items[0]);
  if (v->type == JSON_OBJECT) v->keys[v->count] = key;
  ++v->count;
  return 1;
oom:
  free(key);
  fail(ps, "out of memory");
  return 0;
}

static int parse_container(parser* ps, json_value* v, int depth, char close) {
  size_t capacity = 0;
  v->type = close == '}' ? JSON_OBJECT : JSON_ARRAY;
  if (depth >= MAX_DEPTH) {
    fail(ps, "nested too deeply");
    return 0;
  }
  skip_space(ps);
  if (ps->p < ps->end && *ps->p == close) {
    ++ps->p;
    return 1;
  }
  for (;;) {
    char* key = NULL;
    skip_space(ps);
    if (v->type == JSON_OBJECT) {
      if (ps->p >= ps->end || *ps->p != '"') {
        fail(ps, "expected a member name in quotes");
        return 0;
      }
      ++ps->p;
      if (!(key = parse_string(ps))) return 0;
      skip_space(ps);
      if (ps->p >= ps->end || *ps->p != ':') {
        free(key);
        fail(ps, "expected ':' after a member name");
        return 0;
      }
      ++ps->p;
    }
    if (!push_item(ps, v, &capacity, key)) return 0;
    if (!parse_value(ps, &v->items[v->count - 1], depth + 1)) return 0;
    skip_space(ps);
    if (ps->p < ps->end && *ps->p == ',') {
      ++ps->p;
      continue;
    }
    if (ps->p < ps->end && *ps->p == close) {
      ++ps->p;
      return 1;
    }
    fail(ps, close == '}' ? "expected ',' or '}'" : "expected ',' or ']'");
    return 0;
  }
}

static int parse_value(parser* ps, json_value* v, int depth) {
  skip_space(ps);
  if (ps->p >= ps->end) {
    fail(ps, "unexpected end of input");
    return 0;
  }
  switch (*ps->p) {
    case '{':
      ++ps->p;
      return parse_container(ps, v, depth, '}');
    case '[':
      ++ps->p;
      return parse_container(ps, v, depth, ']');
    case '"':
      ++ps->p;
      v->type = JSON_STRING;
      return (v->string = parse_string(ps)) != NULL;
    case 't':
      v->type = JSON_BOOL;
      v->boolean = 1;
      if (literal(ps, "true")) return 1;
      break;
    case 'f':
      v->type = JSON_BOOL;
      v->boolean = 0;
      if (literal(ps, "false")) return 1;
      break;
    case 'n':
      v->type = JSON_NULL;
      if (literal(ps, "null")) return 1;
      break;
    default:
      v->type = JSON_NUMBER;
      if (parse_number(ps, &v->number)) return 1;
      break;
  }
  fail(ps, "expected a JSON value");
  return 0;
}

static void free_contents(json_value* v) {
  size_t i;
  if (!v) return;
  for (i = 0; i < v->count; ++i) {
    free_contents(&v->items[i]);
    if (v->keys) free(v->keys[i]);
  }
  free(v->items);
  free(v->keys);
  free(v->string);
}

json_value* json_parse(const char* text, size_t length, char* err, size_t err_size) {
  parser ps;
  json_value* root = (json_value*)calloc(1, sizeof *root);
  if (err && err_size) err[0] = '\0';
  if (!root) {
    if (err && err_size) snprintf(err, err_size, "out of memory");
    return NULL;
  }
  ps.start = ps.p = text;
  ps.end = text + length;
  ps.err = err;
  ps.err_size = err_size;
  ps.failed = 0;
  if (length >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0) ps.p += 3;
  if (parse_value(&ps, root, 0)) {
    skip_space(&ps);
    if (ps.p == ps.end) return root;
    fail(&ps, "unexpected text after the JSON value");
  }
  json_free(root);
  return NULL;
}

void json_free(json_value* v) {
  free_contents(v);
  free(v);
}

const json_value* json_get(const json_value* object, const char* key) {
  size_t i;
  if (!object || object->type != JSON_OBJECT) return NULL;
  for (i = object->count; i-- > 0;)
    if (strcmp(object->keys[i], key) == 0) return &object->items[i];
  return NULL;
}

char* json_read_file(const char* path, size_t* length) {
  FILE* f = fopen(path, "rb");
  char* data = NULL;
  size_t size = 0, capacity = 0;
  if (!f) return NULL;
  for (;;) {
    size_t got;
    if (capacity - size < 4096 + 1) {
      char* grown;
      capacity = capacity ? 2 * capacity : 65536;
      grown = (char*)realloc(data, capacity);
      if (!grown) {
        free(data);
        fclose(f);
        return NULL;
      }
      data = grown;
    }
    got = fread(data + size, 1, capacity - size - 1, f);
    size += got;
    if (got == 0) break;
  }
  if (ferror(f)) {
    free(data);
    fclose(f);
    return NULL;
  }
  fclose(f);
  data[size] = '\0';
  if (length) *length = size;
  return data;
}
