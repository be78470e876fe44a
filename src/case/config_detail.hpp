// Checks of case text before it is parsed, shared by the config part's files (private).
#pragma once

#include <string>
#include <vector>

namespace gfmd::config_detail {

// TOML is UTF-8 text: throws InputError(name, ...) at the first malformed sequence.
void require_utf8(const std::string& s, const std::string& name);
// Refuses nesting deeper than kMaxTomlNesting (arrays, inline tables, dotted keys) before
// toml11 recurses into it.
void require_shallow_nesting(const std::string& s, const std::string& name);
// The section names of a case file, in their order.
extern const std::vector<std::string> kSections;

}  // namespace gfmd::config_detail
