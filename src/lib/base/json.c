// The JSON reader (see bk_json.h).
#include "bk_json.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_base.h"

typedef struct json_parser {
  const char* text;
  size_t size, pos;
  bk_json_doc* doc;
  const char* problem; ///< set on the first error
  size_t problem_at;
  const bk_json_limits* limits;
  bool counting;         ///< the first pass: values are counted, not stored
  uint32_t skip;         ///< inside a value kept whole (limits): its children are not stored
  uint64_t total;        ///< values seen, stored or not
  bk_json_value scratch; ///< where the values not stored are written
} json_parser;

// Where a value's fields go: the document, or the scratch value when the
// value is not stored (the counting pass, or a child of a value kept whole).
static bk_json_value* value_of(json_parser* p, uint32_t index) {
  return p->counting || p->skip ? &p->scratch : &p->doc->values[index];
}

static bool fail_at(json_parser* p, const char* problem, size_t at) {
  if (!p->problem) {
    p->problem = problem;
    p->problem_at = at;
  }
  return false;
}

static void skip_space(json_parser* p) {
  while (p->pos < p->size) {
    char c = p->text[p->pos];
    if (c != ' ' && c != '\t' && c != '\n' && c != '\r') break;
    p->pos++;
  }
}

static uint32_t add_value(json_parser* p, bk_json_type type) {
  bk_json_doc* d = p->doc;
  uint32_t index = d->count;
  if (p->limits->max_total && ++p->total > p->limits->max_total) {
    fail_at(p, "too many values", p->pos);
    return BK_JSON_NONE;
  }
  if (!p->skip) {
    // The counting pass refuses here, before the second allocates anything.
    if (d->count >= p->limits->max_values) {
      fail_at(p, "too many values", p->pos);
      return BK_JSON_NONE;
    }
    d->count++;
  }
  bk_json_value* v = value_of(p, index);
  memset(v, 0, sizeof *v);
  v->type = type;
  v->next = BK_JSON_NONE;
  v->start = p->pos;
  return index;
}

// Whether the member `key` of an object at `depth` is kept as one childless value.
static bool keep_whole(const json_parser* p, int depth, const char* key, size_t length) {
  const bk_json_limits* l = p->limits;
  if (l->skip_extras && length == 6 && memcmp(key, "extras", 6) == 0) return true;
  if (!l->top_keys || depth != 0) return false;
  for (const char* const* k = l->top_keys; *k; ++k)
    if (strlen(*k) == length && memcmp(*k, key, length) == 0) return false;
  return true;
}

static bool is_digit(char c) { return c >= '0' && c <= '9'; }

static bool is_hex(char c) { return is_digit(c) || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F'); }

// A string starting at the opening quote; *start/*length get its contents.
static bool parse_string(json_parser* p, size_t* start, size_t* length) {
  size_t open = p->pos++;
  *start = p->pos;
  while (p->pos < p->size) {
    unsigned char c = (unsigned char)p->text[p->pos];
    if (c == '"') {
      *length = p->pos - *start;
      p->pos++;
      return true;
    }
    if (c < 0x20) return fail_at(p, "control character in a string", p->pos);
    if (c == '\\') {
      if (p->pos + 1 >= p->size) break;
      char e = p->text[p->pos + 1];
      if (e == 'u') {
        if (p->size - p->pos < 6) break;
        for (int k = 2; k < 6; ++k)
          if (!is_hex(p->text[p->pos + k])) return fail_at(p, "bad \\u escape in a string", p->pos);
        p->pos += 6;
        continue;
      }
      if (!strchr("\"\\/bfnrt", e) || e == '\0') return fail_at(p, "bad escape in a string", p->pos);
      p->pos += 2;
      continue;
    }
    p->pos++;
  }
  return fail_at(p, "unterminated string", open);
}

static bool parse_number(json_parser* p) {
  size_t at = p->pos;
  if (p->pos < p->size && p->text[p->pos] == '-') p->pos++;
  if (p->pos >= p->size || !is_digit(p->text[p->pos])) return fail_at(p, "bad number", at);
  if (p->text[p->pos] == '0')
    p->pos++;
  else
    while (p->pos < p->size && is_digit(p->text[p->pos]))
      p->pos++;
  if (p->pos < p->size && p->text[p->pos] == '.') {
    p->pos++;
    if (p->pos >= p->size || !is_digit(p->text[p->pos])) return fail_at(p, "bad number", at);
    while (p->pos < p->size && is_digit(p->text[p->pos]))
      p->pos++;
  }
  if (p->pos < p->size && (p->text[p->pos] == 'e' || p->text[p->pos] == 'E')) {
    p->pos++;
    if (p->pos < p->size && (p->text[p->pos] == '+' || p->text[p->pos] == '-')) p->pos++;
    if (p->pos >= p->size || !is_digit(p->text[p->pos])) return fail_at(p, "bad number", at);
    while (p->pos < p->size && is_digit(p->text[p->pos]))
      p->pos++;
  }
  return true;
}

static bool parse_literal(json_parser* p, const char* word) {
  size_t n = strlen(word);
  if (p->size - p->pos < n || memcmp(p->text + p->pos, word, n) != 0)
    return fail_at(p, "unexpected character", p->pos);
  p->pos += n;
  return true;
}

static bool parse_value(json_parser* p, int depth, bool whole, uint32_t* index);

// The children of an array or object whose opening bracket is at p->pos.
static bool parse_container(json_parser* p, uint32_t self, int depth, bool object) {
  char close = object ? '}' : ']';
  p->pos++;
  skip_space(p);
  if (p->pos < p->size && p->text[p->pos] == close) {
    p->pos++;
    return true;
  }
  uint32_t last = BK_JSON_NONE;
  for (;;) {
    size_t key_start = 0, key_length = 0;
    if (object) {
      if (p->pos >= p->size || p->text[p->pos] != '"')
        return fail_at(p, p->pos >= p->size ? "unexpected end of text" : "expected a key", p->pos);
      if (!parse_string(p, &key_start, &key_length)) return false;
      skip_space(p);
      if (p->pos >= p->size || p->text[p->pos] != ':') return fail_at(p, "expected ':'", p->pos);
      p->pos++;
      skip_space(p);
    }
    uint32_t child = 0;
    bool whole = object && keep_whole(p, depth, p->text + key_start, key_length);
    if (!parse_value(p, depth + 1, whole, &child)) return false;
    bk_json_value* c = value_of(p, child);
    c->key_start = key_start;
    c->key_length = key_length;
    if (last != BK_JSON_NONE) value_of(p, last)->next = child;
    last = child;
    value_of(p, self)->count++;
    skip_space(p);
    if (p->pos >= p->size) return fail_at(p, "unexpected end of text", p->pos);
    char c2 = p->text[p->pos];
    if (c2 == close) {
      p->pos++;
      return true;
    }
    if (c2 != ',') return fail_at(p, object ? "expected ',' or '}'" : "expected ',' or ']'", p->pos);
    p->pos++;
    skip_space(p);
  }
}

static bool parse_value(json_parser* p, int depth, bool whole, uint32_t* index) {
  skip_space(p);
  if (p->pos >= p->size) return fail_at(p, "unexpected end of text", p->pos);
  char c = p->text[p->pos];
  uint32_t self = 0;
  bool ok = false;
  switch (c) {
  case '{':
  case '[':
    if (depth >= BK_JSON_MAX_DEPTH) return fail_at(p, "nested too deeply", p->pos);
    self = add_value(p, c == '{' ? BK_JSON_OBJECT : BK_JSON_ARRAY);
    if (self == BK_JSON_NONE) return false;
    p->skip += whole; // its children are checked, not stored
    ok = parse_container(p, self, depth, c == '{');
    p->skip -= whole;
    break;
  case '"': {
    self = add_value(p, BK_JSON_STRING);
    if (self == BK_JSON_NONE) return false;
    size_t start = 0, length = 0;
    ok = parse_string(p, &start, &length);
    value_of(p, self)->start = start;
    value_of(p, self)->length = length;
    *index = self;
    return ok;
  }
  case 't':
    self = add_value(p, BK_JSON_TRUE);
    if (self == BK_JSON_NONE) return false;
    ok = parse_literal(p, "true");
    break;
  case 'f':
    self = add_value(p, BK_JSON_FALSE);
    if (self == BK_JSON_NONE) return false;
    ok = parse_literal(p, "false");
    break;
  case 'n':
    self = add_value(p, BK_JSON_NULL);
    if (self == BK_JSON_NONE) return false;
    ok = parse_literal(p, "null");
    break;
  default:
    self = add_value(p, BK_JSON_NUMBER);
    if (self == BK_JSON_NONE) return false;
    ok = parse_number(p);
    break;
  }
  value_of(p, self)->length = p->pos - value_of(p, self)->start;
  *index = self;
  return ok;
}

bool bk_json_parse(const char* text, size_t size, bk_json_doc* doc, char* why, size_t why_size) {
  static const bk_json_limits all = {BK_JSON_MAX_VALUES, 0, NULL, false};
  return bk_json_parse_limited(text, size, &all, doc, why, why_size);
}

// One pass over the text: counting (doc->values untouched) or storing.
static bool parse_pass(json_parser* p) {
  uint32_t top = 0;
  bool ok = parse_value(p, 0, false, &top);
  if (ok) {
    skip_space(p);
    if (p->pos != p->size) ok = fail_at(p, "unexpected text after the end", p->pos);
  }
  return ok;
}

bool bk_json_parse_limited(const char* text, size_t size, const bk_json_limits* limits, bk_json_doc* doc,
                           char* why, size_t why_size) {
  memset(doc, 0, sizeof *doc);
  doc->text = text;
  doc->size = size;
  json_parser p = {.text = text, .size = size, .doc = doc, .limits = limits, .counting = true};
  // The values are counted first and allocated once, exactly: the grammar
  // and the count limit are checked before any memory is taken for them.
  bool ok = parse_pass(&p);
  if (ok) {
    doc->capacity = doc->count;
    doc->values = bk_alloc(sizeof(bk_json_value) * (doc->count ? doc->count : 1));
    doc->count = 0;
    p.pos = 0;
    p.total = 0;
    p.counting = false;
    ok = parse_pass(&p);
  }
  if (!ok) {
    if (why && why_size) {
      if (p.problem && strcmp(p.problem, "too many values") == 0)
        snprintf(why, why_size, "more than %llu values",
                 (unsigned long long)(p.total > limits->max_total && limits->max_total ? limits->max_total
                                                                                       : limits->max_values));
      else
        snprintf(why, why_size, "%s at byte %zu", p.problem ? p.problem : "malformed", p.problem_at);
    }
    bk_json_free(doc);
    return false;
  }
  return true;
}

void bk_json_free(bk_json_doc* doc) {
  bk_free(doc->values);
  memset(doc, 0, sizeof *doc);
}

static const bk_json_value* value_at(const bk_json_doc* doc, uint32_t value) {
  return value < doc->count ? &doc->values[value] : NULL;
}

uint32_t bk_json_first(const bk_json_doc* doc, uint32_t value) {
  const bk_json_value* v = value_at(doc, value);
  return v && (v->type == BK_JSON_ARRAY || v->type == BK_JSON_OBJECT) && v->count ? value + 1 : BK_JSON_NONE;
}

uint32_t bk_json_next(const bk_json_doc* doc, uint32_t value) {
  const bk_json_value* v = value_at(doc, value);
  return v ? v->next : BK_JSON_NONE;
}

bk_json_type bk_json_type_of(const bk_json_doc* doc, uint32_t value) {
  const bk_json_value* v = value_at(doc, value);
  return v ? v->type : BK_JSON_NULL;
}

uint32_t bk_json_count(const bk_json_doc* doc, uint32_t value) {
  const bk_json_value* v = value_at(doc, value);
  return v && (v->type == BK_JSON_ARRAY || v->type == BK_JSON_OBJECT) ? v->count : 0;
}

uint32_t bk_json_get(const bk_json_doc* doc, uint32_t object, const char* key) {
  if (bk_json_type_of(doc, object) != BK_JSON_OBJECT) return BK_JSON_NONE;
  size_t n = strlen(key);
  for (uint32_t c = bk_json_first(doc, object); c != BK_JSON_NONE; c = bk_json_next(doc, c)) {
    const bk_json_value* v = &doc->values[c];
    if (v->key_length == n && memcmp(doc->text + v->key_start, key, n) == 0) return c;
  }
  return BK_JSON_NONE;
}

uint32_t bk_json_at(const bk_json_doc* doc, uint32_t array, uint32_t i) {
  if (bk_json_type_of(doc, array) != BK_JSON_ARRAY || i >= doc->values[array].count) return BK_JSON_NONE;
  uint32_t c = bk_json_first(doc, array);
  while (i-- > 0 && c != BK_JSON_NONE)
    c = bk_json_next(doc, c);
  return c;
}

bool bk_json_number(const bk_json_doc* doc, uint32_t value, double* out) {
  const bk_json_value* v = value_at(doc, value);
  if (!v || v->type != BK_JSON_NUMBER) return false;
  char literal[128];
  if (v->length >= sizeof literal) return false; // no number we write or read is this long
  memcpy(literal, doc->text + v->start, v->length);
  literal[v->length] = '\0';
  bk_c_locale c_locale = bk_c_locale_begin();
  *out = strtod(literal, NULL);
  bk_c_locale_end(&c_locale);
  return true;
}

bool bk_json_uint(const bk_json_doc* doc, uint32_t value, uint64_t max, uint64_t* out) {
  const bk_json_value* v = value_at(doc, value);
  if (!v || v->type != BK_JSON_NUMBER || v->length == 0 || v->length > 20) return false;
  uint64_t n = 0;
  for (size_t i = 0; i < v->length; ++i) {
    char c = doc->text[v->start + i];
    if (!is_digit(c)) return false;
    uint64_t digit = (uint64_t)(c - '0');
    if (n > (UINT64_MAX - digit) / 10) return false;
    n = n * 10 + digit;
  }
  if (n > max) return false;
  *out = n;
  return true;
}

bool bk_json_string_is(const bk_json_doc* doc, uint32_t value, const char* text) {
  const bk_json_value* v = value_at(doc, value);
  size_t n = strlen(text);
  return v && v->type == BK_JSON_STRING && v->length == n && memcmp(doc->text + v->start, text, n) == 0;
}
