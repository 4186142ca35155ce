// binding_check: the header/binding consistency check (ctest
// bindings_consistency). facesr.h is the truth; the C# and Rust bindings
// must declare every function with the same parameter kinds, every constant
// with the same value, and every struct with the same size and field offsets
// and sizes as the C compiler lays them out.
//
//   binding_check gen-c HEADER OUT.c
//       writes a C program that prints, for every struct of HEADER, sizeof and
//       each field's offsetof/sizeof, and every integer constant's value: the
//       C compiler's view, in the format below.
//   binding_check check --header H --c C.txt --csharp CS.txt --rust RS.txt --rust-sys lib.rs
//       compares. C.txt: the gen-c program's output; CS.txt: CsharpLayout.exe's
//       (structs, constants and DllImports by reflection); RS.txt: facesr-sys's
//       print_layout example's (structs); lib.rs: facesr-sys's source, whose
//       extern "C" block and FACESR_ constants are read here. Exit 0 when all
//       agree, 1 with one line per problem otherwise.
//
// Text format (one record per line, any order):
//   struct <name> size <bytes>
//   field <struct> <field> offset <bytes> size <bytes>
//   const <NAME> <value>
//   function <name> <kind,kind,...|void> <return kind> [<calling convention> <library>]
// Kinds: ptr (any pointer, array, handle, ref/out), i32, u32, i64, u64, f32,
// f64, void, or a struct's C name for a struct passed by value.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

std::string collapse_spaces(const std::string& s) {
  return trim(std::regex_replace(s, std::regex("\\s+"), " "));
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, sep)) out.push_back(part);
  return out;
}

// C and Rust comments removed (newlines kept, so lines stay lines). Neither
// source has comment markers inside string literals.
std::string strip_comments(const std::string& src) {
  std::string out;
  for (size_t i = 0; i < src.size();) {
    if (src.compare(i, 2, "/*") == 0) {
      const size_t end = src.find("*/", i + 2);
      const size_t stop = end == std::string::npos ? src.size() : end + 2;
      for (size_t j = i; j < stop; ++j)
        if (src[j] == '\n') out += '\n';
      i = stop;
    } else if (src.compare(i, 2, "//") == 0) {
      while (i < src.size() && src[i] != '\n') ++i;
    } else {
      out += src[i++];
    }
  }
  return out;
}

struct Field {
  std::string name;
  std::string decl;  // e.g. "float jaw_pivot[3]"
};

struct Header {
  std::map<std::string, std::vector<Field>> structs;  // in declaration order of fields
  std::vector<std::string> struct_order;
  std::map<std::string, long long> constants;
  std::map<std::string, std::string> functions;  // name -> "params ret"
};

// The kind of a C type as binding_check names it ("?" + type if unknown).
std::string c_kind(std::string type, bool array, const std::set<std::string>& structs) {
  if (array || type.find('*') != std::string::npos) return "ptr";
  type = collapse_spaces(std::regex_replace(type, std::regex("\\bconst\\b"), ""));
  static const std::map<std::string, std::string> scalars = {
      {"void", "void"},         {"int32_t", "i32"}, {"uint32_t", "u32"}, {"int64_t", "i64"},
      {"uint64_t", "u64"},      {"float", "f32"},   {"double", "f64"},   {"facesr_status", "i32"},
      {"int", "i32"}};
  const auto it = scalars.find(type);
  if (it != scalars.end()) return it->second;
  if (structs.count(type)) return type;
  return "?" + type;
}

Header parse_header(const std::string& path, std::vector<std::string>& problems) {
  Header h;
  const std::string src = strip_comments(read_file(path));

  // Integer constants: #define FACESR_NAME 123.
  const std::regex define_re("^[ \t]*#[ \t]*define[ \t]+(FACESR_[A-Z0-9_]+)[ \t]+(-?[0-9]+)[ \t]*$");
  std::string code;  // everything but preprocessor lines
  for (const std::string& line : split(src, '\n')) {
    std::smatch m;
    if (std::regex_match(line, m, define_re)) h.constants[m[1]] = std::stoll(m[2]);
    if (trim(line).rfind("#", 0) != 0) code += line + "\n";
  }

  // typedef struct name { fields } name;
  const std::regex struct_re("typedef\\s+struct\\s+(\\w+)\\s*\\{([^}]*)\\}\\s*(\\w+)\\s*;");
  for (std::sregex_iterator it(code.begin(), code.end(), struct_re), end; it != end; ++it) {
    const std::string name = (*it)[1], body = (*it)[2];
    if ((*it)[3] != name) problems.push_back("header: typedef struct " + name + " is named " + std::string((*it)[3]));
    std::vector<Field> fields;
    for (const std::string& raw : split(body, ';')) {
      const std::string decl = collapse_spaces(raw);
      if (decl.empty()) continue;
      std::smatch m;
      if (decl.find(',') != std::string::npos ||
          !std::regex_match(decl, m, std::regex("(.*[^A-Za-z0-9_])([A-Za-z_]\\w*)\\s*(\\[\\s*[0-9]+\\s*\\])?"))) {
        problems.push_back("header: cannot parse field '" + decl + "' of " + name + " (one declarator per field)");
        continue;
      }
      fields.push_back({m[2], decl});
    }
    if (fields.empty()) problems.push_back("header: struct " + name + " has no fields I could read");
    h.structs[name] = fields;
    h.struct_order.push_back(name);
  }
  // Every struct body in the header must have been read.
  const std::regex any_body_re("struct\\s+\\w+\\s*\\{");
  const auto bodies = std::distance(std::sregex_iterator(code.begin(), code.end(), any_body_re), std::sregex_iterator());
  if (size_t(bodies) != h.structs.size())
    problems.push_back("header: " + std::to_string(bodies) + " struct bodies but " + std::to_string(h.structs.size()) +
                       " parsed (only `typedef struct name {...} name;` is understood)");

  std::set<std::string> struct_names;
  for (const auto& s : h.structs) struct_names.insert(s.first);
  const std::regex fn_re("FACESR_API\\s+([^;(]*?)\\b(facesr_\\w+)\\s*\\(([^)]*)\\)\\s*;");
  for (std::sregex_iterator it(code.begin(), code.end(), fn_re), end; it != end; ++it) {
    const std::string name = (*it)[2];
    const std::string ret = c_kind((*it)[1], false, struct_names);
    std::vector<std::string> kinds;
    const std::string params = collapse_spaces((*it)[3]);
    if (params != "void" && !params.empty()) {
      for (const std::string& raw : split(params, ',')) {
        const std::string p = collapse_spaces(raw);
        std::smatch m;
        if (!std::regex_match(p, m, std::regex("(.*[^A-Za-z0-9_])([A-Za-z_]\\w*)\\s*(\\[[^\\]]*\\])?"))) {
          problems.push_back("header: cannot parse parameter '" + p + "' of " + name + " (parameters need names)");
          continue;
        }
        kinds.push_back(c_kind(m[1], m[3].matched, struct_names));
      }
    }
    std::string sig;
    for (const auto& k : kinds) sig += (sig.empty() ? "" : ",") + k;
    if (sig.empty()) sig = "void";
    const std::string full = sig + " " + ret;
    if (full.find('?') != std::string::npos)
      problems.push_back("header: " + name + " has a type binding_check does not know: " + full);
    h.functions[name] = full;
  }
  const std::regex api_re("\\bFACESR_API\\b");
  const auto apis = std::distance(std::sregex_iterator(code.begin(), code.end(), api_re), std::sregex_iterator());
  if (size_t(apis) != h.functions.size())
    problems.push_back("header: " + std::to_string(apis) + " FACESR_API declarations but " +
                       std::to_string(h.functions.size()) + " functions parsed");
  if (h.functions.empty() || h.structs.empty()) problems.push_back("header: no functions or no structs found");
  return h;
}

// ---------------------------------------------------------------- layouts

struct Layout {
  std::map<std::string, long long> struct_size;
  std::map<std::string, std::map<std::string, std::pair<long long, long long>>> fields;  // offset, size
  std::map<std::string, long long> constants;
  std::multimap<std::string, std::vector<std::string>> functions;  // name -> kinds..., ret, [conv, lib]
};

Layout parse_layout(const std::string& path, const std::string& who, std::vector<std::string>& problems) {
  Layout l;
  int n = 0;
  for (const std::string& raw : split(read_file(path), '\n')) {
    ++n;
    std::istringstream in(raw);
    std::vector<std::string> t;
    for (std::string w; in >> w;) t.push_back(w);
    if (t.empty()) continue;
    const std::string where = who + " (" + path + ":" + std::to_string(n) + ")";
    try {
      if (t[0] == "struct" && t.size() == 4 && t[2] == "size") {
        l.struct_size[t[1]] = std::stoll(t[3]);
      } else if (t[0] == "field" && t.size() == 7 && t[3] == "offset" && t[5] == "size") {
        l.fields[t[1]][t[2]] = {std::stoll(t[4]), std::stoll(t[6])};
      } else if (t[0] == "const" && t.size() == 3) {
        l.constants[t[1]] = std::stoll(t[2]);
      } else if (t[0] == "function" && (t.size() == 4 || t.size() == 6)) {
        l.functions.emplace(t[1], std::vector<std::string>(t.begin() + 2, t.end()));
      } else {
        problems.push_back(where + ": cannot read '" + raw + "'");
      }
    } catch (const std::exception&) {
      problems.push_back(where + ": bad number in '" + raw + "'");
    }
  }
  return l;
}

// Structs, fields and (if `check_constants`) constants of `b` against the C
// compiler's `c`.
void compare_layouts(const Layout& c, const Layout& b, const std::string& who, bool check_constants,
                     std::vector<std::string>& problems) {
  for (const auto& [name, size] : c.struct_size) {
    const auto it = b.struct_size.find(name);
    if (it == b.struct_size.end()) {
      problems.push_back(who + ": no binding of struct " + name);
      continue;
    }
    if (it->second != size)
      problems.push_back(who + ": sizeof " + name + " is " + std::to_string(it->second) + ", C has " +
                         std::to_string(size));
    const auto cf = c.fields.find(name);
    const auto bf = b.fields.find(name);
    const std::map<std::string, std::pair<long long, long long>> none;
    const auto& cfields = cf == c.fields.end() ? none : cf->second;
    const auto& bfields = bf == b.fields.end() ? none : bf->second;
    for (const auto& [field, at] : cfields) {
      const auto f = bfields.find(field);
      if (f == bfields.end()) {
        problems.push_back(who + ": " + name + "." + field + " has no binding");
      } else if (f->second != at) {
        problems.push_back(who + ": " + name + "." + field + " is at offset " + std::to_string(f->second.first) +
                           " with size " + std::to_string(f->second.second) + "; C has offset " +
                           std::to_string(at.first) + ", size " + std::to_string(at.second));
      }
    }
    for (const auto& [field, at] : bfields)
      if (!cfields.count(field)) problems.push_back(who + ": " + name + "." + field + " is not a field of facesr.h");
  }
  for (const auto& [name, size] : b.struct_size)
    if (!c.struct_size.count(name)) problems.push_back(who + ": struct " + name + " is not in facesr.h");
  if (check_constants) {
    for (const auto& [name, value] : c.constants) {
      const auto it = b.constants.find(name);
      if (it == b.constants.end())
        problems.push_back(who + ": no constant " + name);
      else if (it->second != value)
        problems.push_back(who + ": " + name + " is " + std::to_string(it->second) + ", facesr.h has " +
                           std::to_string(value));
    }
    for (const auto& [name, value] : b.constants)
      if (!c.constants.count(name)) problems.push_back(who + ": constant " + name + " is not in facesr.h");
  }
}

void compare_functions(const Header& h, const Layout& b, const std::string& who, bool csharp,
                       std::vector<std::string>& problems) {
  for (const auto& [name, sig] : h.functions)
    if (!b.functions.count(name)) problems.push_back(who + ": no binding of " + name + " (" + sig + ")");
  for (const auto& [name, parts] : b.functions) {
    const auto it = h.functions.find(name);
    if (it == h.functions.end()) {
      problems.push_back(who + ": " + name + " is not a function of facesr.h");
      continue;
    }
    const std::string sig = parts[0] + " " + parts[1];
    if (sig != it->second)
      problems.push_back(who + ": " + name + " is declared (" + sig + "); facesr.h has (" + it->second + ")");
    if (csharp) {
      if (parts.size() != 4) {
        problems.push_back(who + ": " + name + " lacks its calling convention and library");
      } else {
        if (parts[2] != "Cdecl")
          problems.push_back(who + ": " + name + " uses CallingConvention." + parts[2] + ", not Cdecl");
        if (parts[3] != "facesr")
          problems.push_back(who + ": " + name + " imports from '" + parts[3] + "', not 'facesr'");
      }
    }
  }
}

// ------------------------------------------------------------ Rust source

// facesr-sys's constants and extern "C" functions, read from its source.
Layout parse_rust_sys(const std::string& path, const std::set<std::string>& structs,
                      std::vector<std::string>& problems) {
  Layout l;
  const std::string src = strip_comments(read_file(path));
  std::map<std::string, std::string> alias;
  const std::regex alias_re("pub\\s+type\\s+(\\w+)\\s*=\\s*(\\w+)\\s*;");
  for (std::sregex_iterator it(src.begin(), src.end(), alias_re), end; it != end; ++it) alias[(*it)[1]] = (*it)[2];
  const std::regex const_re("pub\\s+const\\s+(FACESR_\\w+)\\s*:\\s*\\w+\\s*=\\s*(-?[0-9]+)\\s*;");
  for (std::sregex_iterator it(src.begin(), src.end(), const_re), end; it != end; ++it)
    l.constants[(*it)[1]] = std::stoll((*it)[2]);

  auto kind = [&](std::string t) -> std::string {
    t = collapse_spaces(t);
    if (t.rfind("*", 0) == 0 || t.rfind("&", 0) == 0 || t.rfind("Option<", 0) == 0) return "ptr";
    if (alias.count(t)) t = alias[t];
    static const std::set<std::string> scalars = {"i32", "u32", "i64", "u64", "f32", "f64"};
    if (scalars.count(t) || structs.count(t)) return t;
    if (t == "()") return "void";
    return "?" + t;
  };

  // Only declarations inside extern "C" { ... } blocks are bindings.
  const std::regex block_re("extern\\s+\"C\"\\s*\\{");
  const std::regex fn_re("(?:pub\\s+)?fn\\s+(\\w+)\\s*\\(([^)]*)\\)\\s*(?:->\\s*([^;]+?))?\\s*;");
  int blocks = 0;
  for (std::sregex_iterator it(src.begin(), src.end(), block_re), end; it != end; ++it) {
    ++blocks;
    const size_t open = size_t(it->position() + it->length());
    const size_t close = src.find('}', open);
    const std::string body = src.substr(open, close == std::string::npos ? std::string::npos : close - open);
    for (std::sregex_iterator f(body.begin(), body.end(), fn_re); f != end; ++f) {
      std::vector<std::string> kinds;
      for (const std::string& raw : split((*f)[2], ',')) {
        const std::string p = trim(raw);
        if (p.empty()) continue;  // trailing comma
        const size_t colon = p.find(':');
        if (colon == std::string::npos) {
          problems.push_back("Rust: cannot read parameter '" + p + "' of " + std::string((*f)[1]));
          continue;
        }
        kinds.push_back(kind(p.substr(colon + 1)));
      }
      std::string sig;
      for (const auto& k : kinds) sig += (sig.empty() ? "" : ",") + k;
      if (sig.empty()) sig = "void";
      l.functions.emplace((*f)[1], std::vector<std::string>{sig, (*f)[3].matched ? kind((*f)[3]) : "void"});
    }
  }
  if (blocks == 0) problems.push_back("Rust: no extern \"C\" block in " + path);
  return l;
}

// ------------------------------------------------------------------ gen-c

int gen_c(const std::string& header_path, const std::string& out_path) {
  std::vector<std::string> problems;
  const Header h = parse_header(header_path, problems);
  if (!problems.empty()) {
    for (const auto& p : problems) std::cerr << "binding_check: " << p << "\n";
    return 1;
  }
  std::ostringstream c;
  c << "/* Generated by binding_check gen-c from " << header_path << ": do not edit.\n"
    << " * Prints the C compiler's layout of every struct and the value of every\n"
    << " * constant of the header, in binding_check's format. */\n"
    << "#include <stddef.h>\n#include <stdio.h>\n\n#include \"facesr.h\"\n\n"
    << "#define FIELD(s, f) printf(\"field %s %s offset %lu size %lu\\n\", #s, #f, (unsigned long)offsetof(s, f), "
       "(unsigned long)sizeof(((s*)0)->f))\n\n"
    << "int main(void) {\n";
  for (const std::string& s : h.struct_order) {
    c << "  printf(\"struct %s size %lu\\n\", \"" << s << "\", (unsigned long)sizeof(" << s << "));\n";
    for (const Field& f : h.structs.at(s)) c << "  FIELD(" << s << ", " << f.name << ");\n";
  }
  for (const auto& [name, value] : h.constants)
    c << "  printf(\"const %s %lld\\n\", \"" << name << "\", (long long)(" << name << "));\n";
  c << "  return 0;\n}\n";
  // Written whole to a temporary and renamed, so a failed run leaves no
  // half-written source for the build to compile.
  const std::string tmp = out_path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out << c.str();
    if (!out) {
      std::cerr << "binding_check: cannot write " << tmp << "\n";
      return 1;
    }
  }
  if (std::rename(tmp.c_str(), out_path.c_str()) != 0) {
    std::cerr << "binding_check: cannot rename " << tmp << " to " << out_path << "\n";
    return 1;
  }
  return 0;
}

int check(const std::map<std::string, std::string>& a) {
  for (const char* k : {"--header", "--c", "--csharp", "--rust", "--rust-sys"})
    if (!a.count(k)) {
      std::cerr << "binding_check check: " << k << " FILE is required\n";
      return 2;
    }
  std::vector<std::string> problems;
  const Header h = parse_header(a.at("--header"), problems);
  const Layout c = parse_layout(a.at("--c"), "C", problems);
  const Layout cs = parse_layout(a.at("--csharp"), "C#", problems);
  const Layout rs = parse_layout(a.at("--rust"), "Rust", problems);
  std::set<std::string> structs;
  for (const auto& s : h.structs) structs.insert(s.first);
  const Layout rsys = parse_rust_sys(a.at("--rust-sys"), structs, problems);

  // The compiled C program must describe exactly the header's structs,
  // fields and constants (else it was built from another header).
  for (const auto& [name, fields] : h.structs) {
    if (!c.struct_size.count(name)) problems.push_back("C: the layout program lacks struct " + name);
    for (const Field& f : fields)
      if (!c.fields.count(name) || !c.fields.at(name).count(f.name))
        problems.push_back("C: the layout program lacks " + name + "." + f.name);
  }
  for (const auto& [name, size] : c.struct_size)
    if (!h.structs.count(name)) problems.push_back("C: the layout program has struct " + name + ", not in the header");
  for (const auto& [name, value] : h.constants) {
    const auto it = c.constants.find(name);
    if (it == c.constants.end())
      problems.push_back("C: the layout program lacks constant " + name);
    else if (it->second != value)
      problems.push_back("C: the compiler's " + name + " is " + std::to_string(it->second) + ", the header text says " +
                         std::to_string(value));
  }

  Layout truth = c;
  truth.constants = h.constants;
  compare_layouts(truth, cs, "C#", true, problems);
  compare_layouts(truth, rs, "Rust", false, problems);
  Layout rust_consts;
  rust_consts.constants = rsys.constants;
  Layout header_consts;
  header_consts.constants = h.constants;
  compare_layouts(header_consts, rust_consts, "Rust", true, problems);
  compare_functions(h, cs, "C#", true, problems);
  compare_functions(h, rsys, "Rust", false, problems);

  if (!problems.empty()) {
    std::cerr << "binding_check: the bindings do not match " << a.at("--header") << ":\n";
    for (const auto& p : problems) std::cerr << "  " << p << "\n";
    return 1;
  }
  size_t nfields = 0;
  for (const auto& s : h.structs) nfields += s.second.size();
  std::cout << "binding_check: " << h.functions.size() << " functions, " << h.structs.size() << " structs ("
            << nfields << " fields) and " << h.constants.size()
            << " constants of facesr.h agree in C, C# and Rust\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::vector<std::string> args(argv + 1, argv + argc);
    if (args.size() == 3 && args[0] == "gen-c") return gen_c(args[1], args[2]);
    if (!args.empty() && args[0] == "check" && args.size() % 2 == 1) {
      std::map<std::string, std::string> a;
      for (size_t i = 1; i + 1 < args.size(); i += 2) a[args[i]] = args[i + 1];
      return check(a);
    }
    std::cerr << "usage: binding_check gen-c HEADER OUT.c\n"
                 "       binding_check check --header H --c C.txt --csharp CS.txt --rust RS.txt --rust-sys lib.rs\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "binding_check: " << e.what() << "\n";
    return 1;
  }
}
