// One concept per file, one idea per function: no source file outside tests/ over 600 lines and no
// function over 80 lines. The function scan is deliberately simple and is tested below on made-up
// text:
//  * C++: comments, string and character literals (raw strings too) and preprocessor lines are
//    blanked; then braces are matched. A '{' outside any function opens a function body when the
//    text since the previous ';', '{' or '}' ends in ')' (optionally followed by const, noexcept,
//    override, final, mutable, & or a trailing return type), in a lambda's ']', or closes a
//    constructor's initializer list; namespace, class, struct, union and enum braces are scopes to
//    look inside; any other brace (an initializer) is skipped whole. Braces inside a function
//    (blocks, lambdas) belong to it. A function's length is the lines from its opening brace to its
//    closing one.
//  * Python: a `def` runs until the first non-blank, non-comment line indented no deeper than the
//    `def` (lines inside triple-quoted strings do not end it); its length is from the `def` line to
//    its last non-blank line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "source_tree.hpp"

namespace nmdp::test {
namespace {

constexpr int kMaxFileLines = 600;
constexpr int kMaxFunctionLines = 80;

// The folders whose files the limits apply to (tests/ is exempt from both).
const std::vector<std::string> kSourceTops = {"src", "contact_models", "training", "python", "bench", "fuzz", "scripts"};
const std::vector<std::string> kCppExtensions = {".cpp", ".hpp", ".h", ".cc"};

struct FunctionSpan {
  std::string name;
  int first_line = 0, last_line = 0;  // 1-based, inclusive
  int lines() const { return last_line - first_line + 1; }
};

int lineCount(const std::string& text) {
  if (text.empty()) return 0;
  const int newlines = static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  return text.back() == '\n' ? newlines : newlines + 1;
}

// `text` with comments, literals and preprocessor lines turned into spaces (newlines kept, so that
// positions keep their line numbers).
std::string blankNonCode(const std::string& text) {
  std::string out = text;
  const size_t n = text.size();
  size_t i = 0;
  bool line_start = true;
  const auto blank = [&](size_t from, size_t to) {
    for (size_t k = from; k < to && k < n; ++k)
      if (out[k] != '\n') out[k] = ' ';
  };
  while (i < n) {
    const char c = text[i];
    if (line_start && (c == ' ' || c == '\t')) {
      ++i;
      continue;
    }
    if (line_start && c == '#') {  // a preprocessor line, with its continuations
      size_t end = i;
      while (end < n && !(text[end] == '\n' && text[end - 1] != '\\')) ++end;
      blank(i, end);
      i = end;
      continue;
    }
    line_start = c == '\n';
    if (c == '/' && i + 1 < n && text[i + 1] == '/') {
      const size_t end = text.find('\n', i);
      blank(i, end == std::string::npos ? n : end);
      i = end == std::string::npos ? n : end;
    } else if (c == '/' && i + 1 < n && text[i + 1] == '*') {
      const size_t end = text.find("*/", i + 2);
      const size_t stop = end == std::string::npos ? n : end + 2;
      blank(i, stop);
      i = stop;
    } else if (c == 'R' && i + 1 < n && text[i + 1] == '"' && (i == 0 || !std::isalnum(static_cast<unsigned char>(text[i - 1])))) {
      const size_t open = text.find('(', i + 2);
      const std::string close = ")" + text.substr(i + 2, open - i - 2) + "\"";
      const size_t end = open == std::string::npos ? std::string::npos : text.find(close, open);
      const size_t stop = end == std::string::npos ? n : end + close.size();
      blank(i, stop);
      i = stop;
    } else if (c == '"' || (c == '\'' && !(i > 0 && std::isxdigit(static_cast<unsigned char>(text[i - 1]))))) {
      size_t k = i + 1;  // (a ' after a digit is a digit separator, 1'000)
      while (k < n && text[k] != c && text[k] != '\n') k += text[k] == '\\' ? 2 : 1;
      blank(i, k + 1);
      i = k + 1;
    } else {
      ++i;
    }
  }
  return out;
}

// What a '{' outside any function opens. MemberInit: a member's brace initializer inside a
// constructor's initializer list (`A() : b_{2} {`), which belongs to the head of the body to come.
enum class BraceKind { Scope, Function, MemberInit, Other };

// Classifies a '{' by the code since the previous ';', '{' or '}' (`head`).
BraceKind classifyBrace(const std::string& head) {
  static const std::regex initializer_list(R"(\)\s*:(?!:)\s*[\w:])");
  static const std::regex ends_head(R"([)}]\s*$)");
  static const std::regex function(
      R"(\)\s*((const|noexcept|override|final|mutable|volatile|&|&&)\s*)*(->[^;{}()]*)?\s*$)");
  static const std::regex lambda(R"(\]\s*$)");
  static const std::regex scope(R"((^|\W)(namespace|class|struct|union|enum)(\W|$))");
  static const std::regex extern_c(R"(^\s*extern\s*$)");  // extern "C" { (the string is blanked)
  if (std::regex_search(head, initializer_list))
    return std::regex_search(head, ends_head) ? BraceKind::Function : BraceKind::MemberInit;
  if (std::regex_search(head, function) || std::regex_search(head, lambda)) return BraceKind::Function;
  if (std::regex_search(head, extern_c)) return BraceKind::Scope;
  if (std::regex_search(head, scope) && head.find('=') == std::string::npos) return BraceKind::Scope;
  return BraceKind::Other;
}

// "void Foo::bar(int x) const" → "Foo::bar": the last name before the first '('.
std::string functionName(const std::string& head) {
  const std::string before = head.substr(0, head.find('('));
  static const std::regex name(R"(([~\w:]+|operator\s*\S+)\s*$)");
  std::smatch m;
  if (std::regex_search(before, m, name)) return m[1];
  return "(lambda)";
}

// The function bodies of C++ source `text`, by the brace matching described at the top.
std::vector<FunctionSpan> cppFunctions(const std::string& text) {
  const std::string code = blankNonCode(text);
  std::vector<FunctionSpan> out;
  std::string head;
  int line = 1;
  int depth = 0;  // > 0 inside a region matched whole: a function body, an initializer, a member's
  BraceKind region = BraceKind::Other;  // brace initializer (which then joins the head)
  FunctionSpan current;
  for (const char c : code) {
    if (c == '\n') ++line;
    if (depth > 0) {
      if (c == '{') ++depth;
      if (c == '}' && --depth == 0) {
        if (region == BraceKind::Function) {
          current.last_line = line;
          out.push_back(current);
        }
        if (region == BraceKind::MemberInit) head += '}';
        else head.clear();
      } else if (region == BraceKind::MemberInit) {
        head += c == '\n' ? ' ' : c;
      }
      continue;
    }
    if (c == '{') {
      region = classifyBrace(head);
      if (region == BraceKind::Scope) {
        head.clear();
        continue;
      }
      depth = 1;
      if (region == BraceKind::Function) current = {functionName(head), line, line};
      if (region == BraceKind::MemberInit) head += '{';
      else head.clear();
    } else if (c == '}' || c == ';') {
      head.clear();  // a scope closes, or a declaration ends
    } else {
      head += c == '\n' ? ' ' : c;
    }
  }
  return out;
}

int indentation(const std::string& line) {
  const size_t first = line.find_first_not_of(" \t");
  return first == std::string::npos ? -1 : static_cast<int>(first);
}

// The functions of Python source `text`, by indentation as described at the top.
std::vector<FunctionSpan> pythonFunctions(const std::string& text) {
  std::vector<std::string> lines;
  std::vector<bool> in_string;  // the line starts inside a triple-quoted string
  {
    std::istringstream in(text);
    std::string l;
    bool open = false;
    while (std::getline(in, l)) {
      lines.push_back(l);
      in_string.push_back(open);
      for (const char* quote : {"\"\"\"", "'''"})
        for (size_t at = l.find(quote); at != std::string::npos; at = l.find(quote, at + 3)) open = !open;
    }
  }
  static const std::regex def(R"(^(\s*)(async\s+)?def\s+(\w+))");
  std::vector<FunctionSpan> out;
  for (size_t i = 0; i < lines.size(); ++i) {
    std::smatch m;
    if (in_string[i] || !std::regex_search(lines[i], m, def)) continue;
    const int indent = static_cast<int>(m[1].length());
    size_t last = i;
    for (size_t k = i + 1; k < lines.size(); ++k) {
      const int ind = indentation(lines[k]);
      if (ind < 0) continue;  // blank
      const bool comment = lines[k][ind] == '#';
      if (!in_string[k] && ind <= indent && !comment) break;
      if (in_string[k] || ind > indent || !comment) last = k;  // (a comment after it is not its own)
    }
    out.push_back({m[3], static_cast<int>(i) + 1, static_cast<int>(last) + 1});
  }
  return out;
}

bool isPython(const std::string& path) { return path.size() > 3 && path.substr(path.size() - 3) == ".py"; }

// Test files under scripts/ (test_*.py) are tests: exempt from the function limit.
bool isTestFile(const std::string& path) {
  const std::string name = std::filesystem::path(path).filename().string();
  return name.rfind("test_", 0) == 0;
}

std::vector<std::string> checkedFiles() {
  std::vector<std::string> extensions = kCppExtensions;
  extensions.push_back(".py");
  return sourceFiles(sourceRoot(), kSourceTops, extensions);
}

TEST(SourceSize, NoFileOver600Lines) {
  const std::vector<std::string> files = checkedFiles();
  EXPECT_GT(files.size(), 150u) << "the source tree was not found at " << sourceRoot();
  for (const std::string& file : files) {
    const int lines = lineCount(readText(sourceRoot() / file));
    EXPECT_LE(lines, kMaxFileLines) << file << ": " << lines << " lines";
  }
}

TEST(SourceSize, NoFunctionOver80Lines) {
  int functions = 0;
  for (const std::string& file : checkedFiles()) {
    if (isTestFile(file)) continue;
    const std::string text = readText(sourceRoot() / file);
    for (const FunctionSpan& f : isPython(file) ? pythonFunctions(text) : cppFunctions(text)) {
      ++functions;
      EXPECT_LE(f.lines(), kMaxFunctionLines)
          << file << ":" << f.first_line << ": " << f.name << " is " << f.lines() << " lines";
    }
  }
  EXPECT_GT(functions, 1000) << "the scan found too few functions to be reading the tree";
}

// ----- the scanner itself, on made-up text ----------------------------------------------------------

std::string lines(int n, const std::string& line) {
  std::string s;
  for (int i = 0; i < n; ++i) s += line + "\n";
  return s;
}

// The spans found are `expected` (name, first line, last line), in order.
void expectSpans(const std::vector<FunctionSpan>& found, const std::vector<FunctionSpan>& expected) {
  ASSERT_EQ(found.size(), expected.size());
  for (size_t i = 0; i < found.size(); ++i) {
    EXPECT_EQ(found[i].name, expected[i].name) << i;
    EXPECT_EQ(found[i].first_line, expected[i].first_line) << expected[i].name;
    EXPECT_EQ(found[i].last_line, expected[i].last_line) << expected[i].name;
  }
}

TEST(SourceSizeScanner, CountsLines) {
  EXPECT_EQ(lineCount(""), 0);
  EXPECT_EQ(lineCount("a\nb\n"), 2);
  EXPECT_EQ(lineCount("a\nb"), 2);
}

TEST(SourceSizeScanner, FindsCppFunctionsAndTheirLengths) {
  const std::string text = "namespace nmdp {\n"                              // 1
                           "int f(int x) {\n"                                // 2
                           "  if (x) {\n    return 1;\n  }\n"                // 3-5
                           "  return 0;\n}\n"                                // 6-7
                           "class A : public B {\n public:\n"                // 8-9
                           "  int g() const override { return 1; }\n"        // 10
                           "  A() : a_(1), b_{2} {\n  }\n"                   // 11-12
                           "  int a_, b_;\n};\n"                             // 13-14
                           "const std::vector<int> v = {1, 2, 3};\n"         // 15
                           "auto h(int y) -> int {\n  return y;\n}\n"        // 16-18
                           "}  // namespace nmdp\n";                         // 19
  // The constructor's body opens after its initializer list's b_{2}.
  expectSpans(cppFunctions(text), {{"f", 2, 7}, {"g", 10, 10}, {"A", 11, 12}, {"h", 16, 18}});
}

TEST(SourceSizeScanner, IgnoresBracesInCommentsStringsAndPreprocessorLines) {
  const std::string text = "#define OPEN {\n"
                           "void f() {\n"
                           "  // }\n"
                           "  /* } */ const char* s = \"}\";\n"
                           "  const char* r = R\"x(})\" })x\";\n"
                           "  char c = '}';\n"
                           "  int n = 1'000;\n"
                           "}\n"
                           "void g() {}\n";
  expectSpans(cppFunctions(text), {{"f", 2, 8}, {"g", 9, 9}});
}

TEST(SourceSizeScanner, LambdasAndBlocksBelongToTheirFunction) {
  const std::string text = "void outer() {\n" + lines(3, "  auto l = [&](int x) { return x; };") +
                           "  for (;;) {\n  }\n}\n"
                           "extern \"C\" int LLVMFuzzerTestOneInput(const uint8_t* d, size_t n) {\n  return 0;\n}\n";
  expectSpans(cppFunctions(text), {{"outer", 1, 7}, {"LLVMFuzzerTestOneInput", 8, 10}});
}

TEST(SourceSizeScanner, FlagsAFunctionOverTheLimit) {
  const std::string body = "void long_one() {\n" + lines(kMaxFunctionLines - 1, "  ++x;") + "}\n";
  const std::vector<FunctionSpan> found = cppFunctions(body);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].lines(), kMaxFunctionLines + 1);
}

TEST(SourceSizeScanner, FindsPythonFunctions) {
  const std::string text = "import os\n"               // 1
                           "def f(x):\n"               // 2
                           "    y = x\n"               // 3
                           "\n"                        // 4
                           "# a comment at column 0\n"  // 5
                           "    s = \"\"\"\n"          // 6
                           "text at column 0\n"        // 7
                           "\"\"\"\n"                  // 8
                           "    return y\n"            // 9
                           "\n"                        // 10
                           "class A:\n"                // 11
                           "    def g(self):\n"        // 12
                           "        return 1\n"        // 13
                           "    async def h(self):\n"  // 14
                           "        pass\n"            // 15
                           "X = 1\n";                  // 16
  expectSpans(pythonFunctions(text), {{"f", 2, 9}, {"g", 12, 13}, {"h", 14, 15}});
}

}  // namespace
}  // namespace nmdp::test
