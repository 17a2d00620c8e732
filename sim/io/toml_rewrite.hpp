// Writing a TOML document as an edit of the text it was read from, so that a written scene (best.toml,
// calibrated.toml) is the user's own file with only the changed values replaced: the user's comments,
// key order, spacing and number spellings stay, and `diff scene.toml best.toml` shows the design change
// and nothing else.
//
// The edit walks the updated document against the source's own parse, where every value knows where it
// stands (line and column of its first and past its last character):
//   - a changed number, string or boolean is replaced in place, in its shortest round-trip form
//     (std::to_chars: 7.9811643e-05, never 7.9811643000000003e-05; a float always with '.' or 'e');
//   - an array of the same length is edited element by element (a multi-line array keeps its lines),
//     else replaced whole; a changed inline table is replaced whole;
//   - a new key is inserted after its table's [header] line (at the root: before the first header);
//     a new table, or a new element of an array of tables ([[case]]), is appended at the end;
//   - a removed key's line is deleted.
// The result is then parsed and compared with the updated document (every value, doubles to the bit);
// where anything differs, or the source cannot be edited so (a key defined by dotted keys, a removed
// table), the edit is refused with its reason and the caller writes the document whole.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include <toml++/toml.h>

namespace lg {

struct TomlRewrite {
  std::optional<std::string> text;  // the edited source, if it reproduces 'updated' exactly
  std::string reason;               // why not, when text is empty
};

// The source text 'source' (of the file named 'file') edited to hold the values of 'updated'.
TomlRewrite rewriteToml(std::string_view source, const std::string& file, const toml::table& updated);

// A double in its shortest round-trip form as a TOML float ("3e+06" -> "3e+06", 2.0 -> "2.0",
// inf -> "inf", NaN -> "nan").
std::string tomlFloat(double v);

// Whether two TOML nodes hold the same data: the same types, keys and values (floats compared bit for
// bit, NaN equal to NaN); source positions and formatting flags do not count.
bool sameToml(const toml::node& a, const toml::node& b);

}  // namespace lg
