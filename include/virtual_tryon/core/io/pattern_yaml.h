// The YAML pattern format (documented in config/patterns/README.md), read and written.
#pragma once

#include "virtual_tryon/core/drape/pattern.h"

#include <string>

namespace virtual_tryon {

// Reads / writes the YAML pattern format (documented in config/patterns/README.md).
// Reading checks types, keys (missing, unknown, duplicated) and panel references with messages
// that start with the key path ("panels[1].outline[2]: expected a pair of numbers [u, v], ...
// (line 7, column 16)"), then runs validatePattern (default ratio) on the result. A syntax error
// gives yaml-cpp's message with its line and column. On failure `pattern` is left unchanged and
// false is returned; nothing is thrown. readPatternYaml prefixes messages with the file path.
// patternToYaml writes numbers so that they read back exactly; seams name panels by name when
// the names are unique and non-empty (else by index).
bool readPatternYaml(const std::string& path, Pattern& pattern, std::string& error);
bool parsePatternYaml(const std::string& text, Pattern& pattern, std::string& error);
std::string patternToYaml(const Pattern& pattern);

}  // namespace virtual_tryon
