// Writing output files: atomically (a temporary file in the same folder, flushed, synced, then
// renamed over the target) and checked, so that a reader never sees half a file and a full disk is an
// error, never a silent loss.
#pragma once

#include <string>

namespace lg {

// Writes 'text' to 'path' atomically; throws std::runtime_error naming the path and the cause.
void writeFileAtomic(const std::string& path, const std::string& text);

}  // namespace lg
