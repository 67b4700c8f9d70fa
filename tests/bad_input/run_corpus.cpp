// The bad-input corpus runner (tests/bad_input/README.md): reads one manifest
// of cases, and for each case makes a fresh work directory holding the base
// files (base/), applies the case's edits, runs demcal with the case's
// arguments there, and checks the exit code and that every expected text
// appears in what demcal printed. Exit 0 when every case holds, 1 otherwise
// (each failing case is printed with demcal's output).
//
//   bad_input_corpus <demcal> <corpus dir> <manifest> <work dir>

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Edit {
  std::string op;  // copy, sub, write, append
  std::vector<std::string> args;
};

struct Case {
  std::string name;
  std::size_t line = 0;
  std::vector<Edit> edits;
  std::vector<std::string> runs;  // all but the last must exit 0
  int exit = -1;
  std::vector<std::string> expects;
  std::vector<std::string> absent;  // texts that must not appear
};

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  const auto e = s.find_last_not_of(" \t\r");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

// \n, \t, \\ and \xNN (so that a case can hold a NUL byte or a BOM).
std::string unescape(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '\\' || i + 1 >= s.size()) {
      out += s[i];
      continue;
    }
    const char c = s[++i];
    if (c == 'n') out += '\n';
    else if (c == 't') out += '\t';
    else if (c == '\\') out += '\\';
    else if (c == '|') out += '|';
    else if (c == 'x' && i + 2 < s.size()) {
      out += static_cast<char>(std::stoi(s.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += '\\';
      out += c;
    }
  }
  return out;
}

// "a | b | c" -> {"a", "b", "c"} (a "\|" stays in its field).
std::vector<std::string> fields(const std::string& s) {
  std::vector<std::string> out(1);
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '\\' && i + 1 < s.size() && s[i + 1] == '|') {
      out.back() += "\\|";
      ++i;
    } else if (s[i] == '|') {
      out.emplace_back();
    } else {
      out.back() += s[i];
    }
  }
  for (auto& f : out) f = trim(f);
  return out;
}

std::vector<Case> read_manifest(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot open " + file.string());
  std::vector<Case> cases;
  std::string line;
  std::size_t n = 0;
  auto bad = [&](const std::string& why) {
    throw std::runtime_error(file.string() + ":" + std::to_string(n) + ": " + why);
  };
  while (std::getline(in, line)) {
    ++n;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    const auto colon = t.find(':');
    if (colon == std::string::npos) bad("expected \"key: value\"");
    const std::string key = t.substr(0, colon);
    const std::string value = trim(t.substr(colon + 1));
    if (key == "case") {
      cases.push_back({});
      cases.back().name = value;
      cases.back().line = n;
      continue;
    }
    if (cases.empty()) bad("a case starts with \"case: NAME\"");
    Case& c = cases.back();
    if (key == "run") c.runs.push_back(value);
    else if (key == "exit") c.exit = std::stoi(value);
    else if (key == "expect") c.expects.push_back(unescape(value));
    else if (key == "absent") c.absent.push_back(unescape(value));
    else if (key == "copy" || key == "sub" || key == "write" || key == "append") {
      Edit e{key, fields(value)};
      const std::size_t want = key == "sub" ? 3 : 2;
      if (e.args.size() != want) bad(key + " takes " + std::to_string(want) + " fields separated by |");
      c.edits.push_back(std::move(e));
    } else {
      bad("unknown key \"" + key + "\"");
    }
  }
  std::set<std::string> names;
  for (const Case& c : cases) {
    n = c.line;
    if (!names.insert(c.name).second) bad("case " + c.name + " is named twice");
    if (c.runs.empty()) bad("case " + c.name + " has no run:");
    if (c.exit < 0) bad("case " + c.name + " has no exit:");
    if (c.exit != 0 && c.expects.empty()) bad("case " + c.name + " expects no text");
  }
  return cases;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void spit(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream out(p, std::ios::binary);
  out << text;
}

std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Runs `demcal <args>` in `dir` through the shell; returns the exit code, the output in `text`.
int run(const std::string& demcal, const fs::path& dir, const std::string& args, std::string& text) {
  const fs::path log = dir / ".output";
  const std::string cmd = "cd " + quoted(dir.string()) + " && timeout 120 " + quoted(demcal) + " " + args +
                          " > " + quoted(log.string()) + " 2>&1";
  const int status = std::system(cmd.c_str());
  text = slurp(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::cerr << "usage: bad_input_corpus <demcal> <corpus dir> <manifest> <work dir>\n";
    return 2;
  }
  const std::string demcal = fs::absolute(argv[1]).string();
  const fs::path corpus = fs::absolute(argv[2]);
  const fs::path manifest = argv[3];
  const fs::path work = fs::absolute(argv[4]);
  std::vector<Case> cases;
  try {
    cases = read_manifest(manifest);
  } catch (const std::exception& e) {
    std::cerr << "bad manifest: " << e.what() << "\n";
    return 1;
  }
  std::size_t failed = 0;
  for (const Case& c : cases) {
    const fs::path dir = work / c.name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const auto& f : fs::directory_iterator(corpus / "base")) fs::copy_file(f.path(), dir / f.path().filename());
    std::string problem;
    for (const Edit& e : c.edits) {
      const fs::path target = dir / e.args[0];
      if (e.op == "copy") {
        fs::create_directories((dir / e.args[1]).parent_path());
        fs::copy(corpus / e.args[0], dir / e.args[1], fs::copy_options::overwrite_existing | fs::copy_options::recursive);
      } else if (e.op == "write") {
        spit(target, unescape(e.args[1]));
      } else if (e.op == "append") {
        spit(target, slurp(target) + unescape(e.args[1]));
      } else {  // sub
        std::string text = slurp(target);
        const std::string from = unescape(e.args[1]);
        const auto pos = text.find(from);
        if (pos == std::string::npos) {
          problem = "sub: \"" + e.args[1] + "\" is not in " + e.args[0];
          break;
        }
        text.replace(pos, from.size(), unescape(e.args[2]));
        spit(target, text);
      }
    }
    std::string output;
    int code = -1;
    for (std::size_t i = 0; problem.empty() && i < c.runs.size(); ++i) {
      code = run(demcal, dir, c.runs[i], output);
      if (i + 1 < c.runs.size() && code != 0)
        problem = "setup run \"" + c.runs[i] + "\" exited " + std::to_string(code);
    }
    if (problem.empty() && code != c.exit)
      problem = "exit code " + std::to_string(code) + ", expected " + std::to_string(c.exit);
    for (const std::string& e : c.expects)
      if (problem.empty() && output.find(e) == std::string::npos) problem = "the output lacks \"" + e + "\"";
    for (const std::string& a : c.absent)
      if (problem.empty() && output.find(a) != std::string::npos) problem = "the output holds \"" + a + "\"";
    if (!problem.empty()) {
      ++failed;
      std::cout << "FAILED " << manifest.filename().string() << ":" << c.line << ": " << c.name << ": " << problem
                << "\n  demcal " << c.runs.back() << "\n  output:\n" << output << "\n";
    }
  }
  std::cout << manifest.filename().string() << ": " << cases.size() - failed << " of " << cases.size()
            << " cases hold\n";
  return failed == 0 ? 0 : 1;
}
