// base (private): a small JSON reader for the glTF loader, the glTF model
// check of the import and the tests that read our exports back. It parses the
// whole text into a flat array of values in document order, checking the
// grammar strictly, with the nesting depth limited, every index
// bounds-checked and one-line errors. Strings are kept as raw spans (escapes
// are validated, not decoded); keys compare byte for byte, which is enough
// for the names glTF uses. Hand-written rather than cJSON or jansson: on our
// largest .gltf (151 MB) cJSON took 232 ms for the loader's members against
// 171 ms here (it copies the buffer's base64 string), jansson 1.8 s for the
// whole text against 0.17 s.
#pragma once

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/// Deepest nesting of arrays and objects accepted.
#define BK_JSON_MAX_DEPTH 64
/// Most values in one document (a 65,536-fragment export has about 17 million).
#define BK_JSON_MAX_VALUES (1u << 25)
/// "No such value".
#define BK_JSON_NONE UINT32_MAX

typedef enum bk_json_type {
  BK_JSON_NULL,
  BK_JSON_FALSE,
  BK_JSON_TRUE,
  BK_JSON_NUMBER,
  BK_JSON_STRING,
  BK_JSON_ARRAY,
  BK_JSON_OBJECT,
} bk_json_type;

/// One value. Its children (members of an object, elements of an array)
/// follow it in the array: the first is at its index + 1, the others are
/// linked by `next`.
typedef struct bk_json_value {
  bk_json_type type;
  uint32_t next;        ///< the next sibling, or BK_JSON_NONE
  uint32_t count;       ///< children of an array or object
  size_t start, length; ///< text span: a string's contents (no quotes), a number's literal, a container's
                        ///< whole text
  size_t key_start, key_length; ///< for a member of an object: its key's contents
} bk_json_value;

typedef struct bk_json_doc {
  const char* text;
  size_t size;
  bk_json_value* values; ///< values[0] is the document's top value
  uint32_t count, capacity;
} bk_json_doc;

/// Parses `size` bytes of text (not necessarily NUL-terminated). On failure
/// `why` gets "<problem> at byte <offset>" (or "more than N values") and the
/// doc is left empty. The values are counted before they are allocated, once.
bool bk_json_parse(const char* text, size_t size, bk_json_doc* doc, char* why, size_t why_size);

/// What a reader needs of a document: values it never looks at are checked
/// but not stored, each kept as one value of its type with no children.
typedef struct bk_json_limits {
  uint32_t max_values;         ///< most values stored (at most BK_JSON_MAX_VALUES)
  uint64_t max_total;          ///< most values in the text, stored or not (0: no limit)
  const char* const* top_keys; ///< the top object's members stored whole (NULL-terminated); NULL = all
  bool skip_extras;            ///< every "extras" member is kept without its contents
} bk_json_limits;
/// bk_json_parse storing only what `limits` keeps.
bool bk_json_parse_limited(const char* text, size_t size, const bk_json_limits* limits, bk_json_doc* doc,
                           char* why, size_t why_size);
/// Releases the values.
void bk_json_free(bk_json_doc* doc);

/// The member of an object with this key (the first, if repeated), or BK_JSON_NONE
/// (also when `object` is none or not an object).
uint32_t bk_json_get(const bk_json_doc* doc, uint32_t object, const char* key);
/// Element i of an array, or BK_JSON_NONE.
uint32_t bk_json_at(const bk_json_doc* doc, uint32_t array, uint32_t i);
/// First child of an array or object, or BK_JSON_NONE.
uint32_t bk_json_first(const bk_json_doc* doc, uint32_t value);
/// Next sibling, or BK_JSON_NONE.
uint32_t bk_json_next(const bk_json_doc* doc, uint32_t value);
/// Type of a value; BK_JSON_NULL for BK_JSON_NONE as well.
bk_json_type bk_json_type_of(const bk_json_doc* doc, uint32_t value);
/// Children of an array or object (0 otherwise).
uint32_t bk_json_count(const bk_json_doc* doc, uint32_t value);
/// A number's value (strtod in the C locale); false if not a number.
bool bk_json_number(const bk_json_doc* doc, uint32_t value, double* out);
/// A non-negative integer literal (digits only) no larger than max; false otherwise.
bool bk_json_uint(const bk_json_doc* doc, uint32_t value, uint64_t max, uint64_t* out);
/// True when the value is a string whose raw contents equal `text`.
bool bk_json_string_is(const bk_json_doc* doc, uint32_t value, const char* text);
