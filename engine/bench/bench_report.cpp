#include "bench/bench_report.h"

#include <cctype>
#include <ctime>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/atomic_file.h"
#include "core/error.h"

namespace facesr {

namespace {

// The CPU's name, and its family and model numbers when /proc/cpuinfo gives
// them: virtual machines often report a bare "AMD EPYC" or "Intel(R) Xeon(R)
// Processor" for CPUs generations apart (a Zen 1 with AVX2 and a Zen 5 with
// AVX-512 both read "AMD EPYC"), and their speeds must not share a section.
std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line, name = "unknown CPU", family, model;
  auto value = [&] { return line.substr(line.find(':') + 2); };
  while (std::getline(in, line) && line.find_first_not_of(" \t") != std::string::npos) {
    if (line.rfind("model name", 0) == 0)
      name = value();
    else if (line.rfind("cpu family", 0) == 0)
      family = value();
    else if (line.rfind("model", 0) == 0 && line.find(':') != std::string::npos)
      model = value();
  }
  if (!family.empty() && !model.empty()) name += " (family " + family + ", model " + model + ")";
  return name;
}

}  // namespace

std::string machine_description() {
  return cpu_model() + ", " + std::to_string(std::thread::hardware_concurrency()) + " cores";
}

std::string machine_slug() {
  std::string slug;
  for (char c : cpu_model()) {
    if (std::isalnum(static_cast<unsigned char>(c)))
      slug += char(std::tolower(static_cast<unsigned char>(c)));
    else if (!slug.empty() && slug.back() != '-')
      slug += '-';
  }
  while (!slug.empty() && slug.back() == '-') slug.pop_back();
  return slug.empty() ? "unknown-cpu" : slug;
}

std::string today_iso() {
  const std::time_t t = std::time(nullptr);
  char buf[16];
  std::strftime(buf, sizeof buf, "%Y-%m-%d", std::localtime(&t));
  return buf;
}

void update_markdown_section(const std::string& path, const std::string& tag, const std::string& body) {
  std::string text;
  {
    std::ifstream in(path, std::ios::binary);
    if (in) {
      std::stringstream ss;
      ss << in.rdbuf();
      text = ss.str();
    }
  }
  const std::string start = "<!-- " + tag + ":start -->", end = "<!-- " + tag + ":end -->";
  const std::string block = start + "\n" + body + (body.empty() || body.back() == '\n' ? "" : "\n") + end;
  const size_t a = text.find(start), b = text.find(end);
  if (a != std::string::npos && b != std::string::npos && b > a) {
    text = text.substr(0, a) + block + text.substr(b + end.size());
  } else {
    require(a == std::string::npos && b == std::string::npos,
            path + ": unbalanced '" + tag + "' section markers; fix the file by hand");
    if (!text.empty() && text.back() != '\n') text += "\n";
    text += "\n" + block + "\n";
  }
  write_file_atomically(path, [&](std::ostream& os) { os << text; });
}

}  // namespace facesr
