#pragma once
// Pieces of one-line error messages (error.h): outside values quoted and cut, and third-party
// library texts translated into our form.
//
//   fail("%s: unknown value %s", where, quote(value).c_str());   // "xxxx..."... (2097152 bytes)
//   fail("%s: cannot read VDB file: %s", file, library_message(e.what()).c_str());
#include <cstddef>
#include <string>
#include <string_view>

namespace cumulo {

// An outside value quoted for a message: "..." with control characters escaped (a message stays one
// line) and cut after `max` bytes with the full length noted, so a 2 MB string is not echoed back.
std::string quote(std::string_view value, size_t max = 80);
// The same cut without quotes, for values printed as they are (keys in JSON paths, tokens).
std::string clip(std::string_view value, size_t max = 80);

// A third-party library's exception text in our one-line form: its internal prefixes
// ("[json.exception.out_of_range.406] ", OpenVDB's "IoError: ", "RuntimeError: ", ...) removed,
// newlines joined with "; " and the length clipped.
std::string library_message(std::string_view what);

}  // namespace cumulo
