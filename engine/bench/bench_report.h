#pragma once
#include <string>

namespace facesr {

// "AMD EPYC (family 26, model 2), 2 cores" from /proc/cpuinfo and the
// scheduler's CPU count.
std::string machine_description();
// The CPU model as a Markdown-tag-safe word ("amd-epyc-family-26-model-2"): speed
// benchmarks keep one section per rig and machine, so that a run on another
// machine adds its numbers instead of replacing the last machine's.
std::string machine_slug();
// Today's date, YYYY-MM-DD (local time).
std::string today_iso();

// Replaces the text between "<!-- <tag>:start -->" and "<!-- <tag>:end -->"
// in a Markdown file (appending the marked section when absent, creating the
// file when missing), atomically.
void update_markdown_section(const std::string& path, const std::string& tag, const std::string& body);

}  // namespace facesr
