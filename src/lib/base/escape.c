// The escaping of text quoted from a file in a message (bk_error_set applies
// it to every message), so no file can drive the user's terminal.
#include <stdio.h>
#include <string.h>

#include "bk_base.h"

// Length of the UTF-8 sequence at s (at most `left` bytes) when it is one a
// terminal prints (valid, not a C1 control U+0080..U+009F); 0 otherwise.
static size_t printable_utf8(const unsigned char* s, size_t left) {
  size_t length = s[0] >= 0xc2 && s[0] <= 0xdf   ? 2
                  : s[0] >= 0xe0 && s[0] <= 0xef ? 3
                  : s[0] >= 0xf0 && s[0] <= 0xf4 ? 4
                                                 : 0;
  if (length == 0 || length > left) return 0;
  for (size_t i = 1; i < length; ++i)
    if ((s[i] & 0xc0) != 0x80) return 0;
  if (s[0] == 0xc2 && s[1] < 0xa0) return 0;  // C1 controls
  if (s[0] == 0xe0 && s[1] < 0xa0) return 0;  // overlong
  if (s[0] == 0xed && s[1] >= 0xa0) return 0; // surrogates
  if (s[0] == 0xf0 && s[1] < 0x90) return 0;  // overlong
  if (s[0] == 0xf4 && s[1] >= 0x90) return 0; // past U+10FFFF
  return length;
}

size_t bk_escape_text(const char* text, size_t length, char* out, size_t size) {
  const unsigned char* s = (const unsigned char*)text;
  size_t used = 0, i = 0;
  while (i < length) {
    size_t n = s[i] >= 0x20 && s[i] < 0x7f ? 1 : s[i] >= 0x80 ? printable_utf8(s + i, length - i) : 0;
    if (n > 0) {
      if (used + n >= size) break;
      memcpy(out + used, s + i, n);
      used += n;
      i += n;
    } else {
      if (used + 4 >= size) break;
      snprintf(out + used, size - used, "\\x%02x", s[i]);
      used += 4;
      i += 1;
    }
  }
  if (size > 0) out[used] = 0;
  return i;
}
