#pragma once
#include <string>

namespace facesr {

// "AMD EPYC 7B13, 2 cores" from /proc/cpuinfo and the scheduler's CPU count.
std::string machine_description();
// Today's date, YYYY-MM-DD (local time).
std::string today_iso();

// Replaces the text between "<!-- <tag>:start -->" and "<!-- <tag>:end -->"
// in a Markdown file (appending the marked section when absent, creating the
// file when missing), atomically.
void update_markdown_section(const std::string& path, const std::string& tag, const std::string& body);

}  // namespace facesr
