#include "deploysim/io/yaml_fields.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace deploysim::io::yaml {

struct YamlNode::Impl {
  YAML::Node node;
};

namespace {

YamlNode Wrap(const YAML::Node& node) {
  return YamlNode(std::make_shared<const YamlNode::Impl>(YamlNode::Impl{node}));
}

const YAML::Node& Y(const YamlNode& node) { return node.impl().node; }

constexpr std::size_t kMaxRenderedLength = 80;

std::string Join(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// Nesting rendered before "...": bounds the recursion, which a self-referencing anchor
// (`a: &a [*a]`) would otherwise make endless (such documents are refused by the parse
// guard below; nodes built in code are not).
constexpr int kMaxRenderedDepth = 8;

/// Appends `node` to `out` in flow style, stopping once `out` is longer than
/// kMaxRenderedLength: the work is bounded by the output, not by the node (a node reached
/// by 10^9 paths through aliases costs no more than any other).
void RenderInto(const YAML::Node& node, int depth, std::string& out) {
  if (out.size() > kMaxRenderedLength) return;
  if (depth > kMaxRenderedDepth) {
    out += "...";
    return;
  }
  switch (node.Type()) {
    case YAML::NodeType::Undefined:
    case YAML::NodeType::Null:
      out += "null";
      return;
    case YAML::NodeType::Scalar: {
      // Quoted scalars keep their quotes, so that `"60"` reads as the string it is.
      const bool quoted = node.Tag() == "!";
      const std::string& v = node.Scalar();
      out += quoted ? "\"" : "";
      // Inside a collection shorter, so that the rest shows too.
      const std::size_t shown = depth == 0 ? kMaxShownBytes : kMaxShownBytes / 3;
      out += v.size() > shown ? ShortValue(v, shown) : v;
      out += quoted ? "\"" : "";
      return;
    }
    case YAML::NodeType::Sequence: {
      out += "[";
      bool first = true;
      for (const YAML::Node& e : node) {
        if (out.size() > kMaxRenderedLength) return;
        out += first ? "" : ", ";
        RenderInto(e, depth + 1, out);
        first = false;
      }
      out += "]";
      return;
    }
    case YAML::NodeType::Map: {
      out += "{";
      bool first = true;
      for (const auto& kv : node) {
        if (out.size() > kMaxRenderedLength) return;
        out += first ? "" : ", ";
        RenderInto(kv.first, depth + 1, out);
        out += ": ";
        RenderInto(kv.second, depth + 1, out);
        first = false;
      }
      out += "}";
      return;
    }
  }
  out += "?";
}

/// Length of the longest prefix of `s` of at most `n` bytes that ends on a UTF-8
/// character boundary.
std::size_t Utf8Prefix(const std::string& s, std::size_t n) {
  if (n >= s.size()) return s.size();
  while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80) --n;
  return n;
}

/// Control characters as visible escapes (one line per message).
std::string Escaped(const std::string& s) {
  std::string out;
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (u < 0x20 || u == 0x7F) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    } else {
      out += c;
    }
  }
  return out;
}

/// Where a check of text failed: byte offset and the rule broken.
struct TextFault {
  std::size_t offset = 0;
  std::string rule;
};

/// Checks that `s` is UTF-8 (RFC 3629: no overlong forms, no surrogates, at most
/// U+10FFFF) and holds no control characters other than tab, LF and CR (YAML 1.2,
/// c-printable; NEL U+0085 allowed). Returns the first fault, if any.
std::optional<TextFault> CheckText(const std::string& s) {
  const auto* b = reinterpret_cast<const unsigned char*>(s.data());
  const std::size_t n = s.size();
  auto hex = [](unsigned v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%02x", v);
    return std::string(buf);
  };
  for (std::size_t i = 0; i < n;) {
    const unsigned c = b[i];
    if (c < 0x80) {
      if ((c < 0x20 && c != '\t' && c != '\n' && c != '\r') || c == 0x7F) {
        return TextFault{
            i, "control character " + hex(c) + " (only tab, LF and CR are allowed in YAML text)"};
      }
      ++i;
      continue;
    }
    std::size_t len = 0;
    unsigned lo = 0x80, hi = 0xBF;  // range of the second byte
    if (c >= 0xC2 && c <= 0xDF) {
      len = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
      len = 3;
      if (c == 0xE0) lo = 0xA0;  // no overlong forms
      if (c == 0xED) hi = 0x9F;  // no surrogates U+D800..U+DFFF
    } else if (c >= 0xF0 && c <= 0xF4) {
      len = 4;
      if (c == 0xF0) lo = 0x90;
      if (c == 0xF4) hi = 0x8F;  // at most U+10FFFF
    } else {
      return TextFault{i, "invalid UTF-8 (byte " + hex(c) + "): YAML text must be UTF-8"};
    }
    if (i + len > n) return TextFault{i, "invalid UTF-8 (truncated character at the end)"};
    for (std::size_t k = 1; k < len; ++k) {
      const unsigned d = b[i + k];
      if (d < (k == 1 ? lo : 0x80) || d > (k == 1 ? hi : 0xBF)) {
        return TextFault{i, "invalid UTF-8 (byte " + hex(c) + " followed by " + hex(d) +
                                "): YAML text must be UTF-8"};
      }
    }
    if (len == 2) {
      const unsigned cp = ((c & 0x1Fu) << 6) | (b[i + 1] & 0x3Fu);
      if (cp >= 0x80 && cp <= 0x9F && cp != 0x85) {
        return TextFault{i, "control character U+00" + hex(cp).substr(2) +
                                " (only tab, LF and CR are allowed in YAML text)"};
      }
    }
    i += len;
  }
  return std::nullopt;
}

/// Raised inside the event handler; turned into a one-line message by ParseOneDocument.
struct ParseLimit {
  YAML::Mark mark;
  std::string rule;
};

/// First pass over the text (YAML::Parser events, no nodes built), which every document
/// passes before yaml-cpp builds its nodes. It bounds, with every alias expanded, the
/// number of nodes (kMaxNodes) and the nesting depth (kMaxDepth); refuses an alias to a
/// node that contains it (`a: &a [*a]`: an infinite tree), string values that are not UTF-8
/// text (escapes such as "\0" or "\uD800" make them), and stops yaml-cpp 0.7's document
/// loop (see ParseOneDocument). Linear in the text: per node, a few integers.
class GuardHandler : public YAML::EventHandler {
 public:
  explicit GuardHandler(const std::string& text) : text_(text) {}
  std::size_t documents() const { return documents_; }

  void OnDocumentStart(const YAML::Mark& mark) override {
    // yaml-cpp 0.7 (upstream bug report no. 1040, fixed by pull request 1319): on a token that no
    // rule consumes (a ',' outside a flow collection: `,` `!,` `a: ,` `- ,`) the parser emits an
    // empty document without advancing, forever; LoadAll collects them until memory runs out. A
    // document that starts where the previous one started is that loop.
    if (documents_ > 0 && mark.pos == last_start_.pos) {
      const std::size_t pos = static_cast<std::size_t>(std::max(mark.pos, 0));
      const std::string c = pos < text_.size() ? text_.substr(pos, 1) : std::string();
      throw ParseLimit{mark, "YAML syntax error: unexpected '" + ShortValue(c) +
                                 "' (',' separates entries only inside [ ] or { })"};
    }
    last_start_ = mark;
    ++documents_;
    root_ = Size{};
    anchors_.clear();  // yaml-cpp numbers the anchors of each document from 1
  }
  void OnDocumentEnd() override {}

  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override { Leaf(mark, anchor); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    Event(mark);
    if (anchor >= anchors_.size() || !anchors_[anchor].defined) {
      throw ParseLimit{mark,
                       "an alias refers to a node that contains it (a recursive alias "
                       "makes an infinite tree)"};
    }
    Add(mark, anchors_[anchor]);
  }
  void OnScalar(const YAML::Mark& mark,
                const std::string& /*tag*/,
                YAML::anchor_t anchor,
                const std::string& value) override {
    if (const std::optional<TextFault> fault = CheckText(value)) {
      throw ParseLimit{mark, "string value " + ShortValue(value) + ": " + fault->rule};
    }
    Leaf(mark, anchor);
  }
  void OnSequenceStart(const YAML::Mark& mark,
                       const std::string& /*tag*/,
                       YAML::anchor_t anchor,
                       YAML::EmitterStyle::value /*style*/) override {
    Open(mark, anchor);
  }
  void OnSequenceEnd() override { Close(); }
  void OnMapStart(const YAML::Mark& mark,
                  const std::string& /*tag*/,
                  YAML::anchor_t anchor,
                  YAML::EmitterStyle::value /*style*/) override {
    Open(mark, anchor);
  }
  void OnMapEnd() override { Close(); }

 private:
  /// A node's tree with aliases expanded: its node count and its depth in nested
  /// collections (a scalar: 1, 0; `[1]`: 2, 1).
  struct Size {
    std::size_t nodes = 0;
    int depth = 0;
    bool defined = false;  ///< For anchors: the node is complete.
  };
  struct Frame {
    YAML::Mark mark;
    YAML::anchor_t anchor;
    Size size;
  };

  void Event(const YAML::Mark& mark) {
    // Raw events are bounded too (each is also a node, so this never binds before the
    // expanded count does, unless the parser stops advancing).
    if (++events_ > kMaxNodes) {
      throw ParseLimit{mark, "more than " + std::to_string(kMaxNodes) + " YAML nodes"};
    }
  }
  void Define(YAML::anchor_t anchor, const Size& size) {
    if (anchor == YAML::NullAnchor) return;
    if (anchor >= anchors_.size()) anchors_.resize(anchor + 1);
    anchors_[anchor] = size;
  }
  void Leaf(const YAML::Mark& mark, YAML::anchor_t anchor) {
    Event(mark);
    const Size one{1, 0, true};
    Define(anchor, one);
    Add(mark, one);
  }
  void Open(const YAML::Mark& mark, YAML::anchor_t anchor) {
    Event(mark);
    Define(anchor, Size{});  // not defined until closed: an alias to it inside is recursive
    stack_.push_back(Frame{mark, anchor, Size{1, 0, true}});
    CheckDepth(mark, static_cast<int>(stack_.size()));
  }
  void Close() {
    Frame f = stack_.back();
    stack_.pop_back();
    f.size.depth += 1;
    Define(f.anchor, f.size);
    Add(f.mark, f.size);
  }
  /// Adds a child of expanded size `s` to the open collection (or the document).
  void Add(const YAML::Mark& mark, const Size& s) {
    Size& parent = stack_.empty() ? root_ : stack_.back().size;
    parent.nodes += s.nodes;  // both <= kMaxNodes: no overflow
    parent.depth = std::max(parent.depth, s.depth);
    if (parent.nodes > kMaxNodes) {
      throw ParseLimit{mark, "more than " + std::to_string(kMaxNodes) +
                                 " YAML nodes (aliases counted as the nodes they repeat)"};
    }
    CheckDepth(mark, static_cast<int>(stack_.size()) + s.depth);
  }
  void CheckDepth(const YAML::Mark& mark, int depth) const {
    if (depth > kMaxDepth) {
      throw ParseLimit{mark, "sequences and mappings nested more than " +
                                 std::to_string(kMaxDepth) +
                                 " deep (aliases counted as the nodes they repeat)"};
    }
  }

  const std::string& text_;
  std::size_t documents_ = 0;
  std::size_t events_ = 0;
  YAML::Mark last_start_;
  Size root_;
  std::vector<Frame> stack_;
  std::vector<Size> anchors_;  ///< By yaml-cpp's anchor id (1, 2, ...).
};

/// Parses the single document of `text`, with the guard first (one line for any error).
///
/// Why a guard and not another parser: yaml-cpp 0.7's loop is in LoadAll's document loop
/// only. Tried on every 1- and 2-byte input (65,792) in a child process under a 512 MB
/// address-space limit and a 2 s alarm: LoadAll ran out of memory on 262 of them (`,` and
/// every input with a ',' at top level: `,x`, `x,` for x in NUL, tab, LF, space, '!'),
/// YAML::Load (one document) on none. The guard walks the same parser's events, stops at
/// the first document that makes no progress and counts nodes and depth; then YAML::Load
/// builds the nodes. Both passes are linear in the text; the guard costs about as much as
/// the parse (no nodes), and adds what a different parser would still need: node, depth
/// and alias bounds. Exhaustive tests: tests/io_yaml/hostile_yaml_test.cpp.
YAML::Node ParseOneDocument(const std::string& path, const std::string& text) {
  auto where = [&path](const YAML::Mark& m) {
    return path + ": line " + std::to_string(m.line + 1) + ", column " +
           std::to_string(m.column + 1) + ": ";
  };
  GuardHandler guard(text);
  try {
    std::istringstream in(text);
    YAML::Parser parser(in);
    while (parser.HandleNextDocument(guard)) {
    }
  } catch (const ParseLimit& e) {
    throw std::invalid_argument(where(e.mark) + e.rule);
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument(where(e.mark) + "YAML syntax error: " + ShortValue(e.msg, 200));
  }
  if (guard.documents() > 1) {
    throw std::invalid_argument(path + ": " + std::to_string(guard.documents()) +
                                " YAML documents ('---'): one document per file");
  }
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument(where(e.mark) + "YAML syntax error: " + ShortValue(e.msg, 200));
  }
}

const char* FileType(mode_t mode) {
  if (S_ISDIR(mode)) return "is a directory";
  if (S_ISCHR(mode)) return "is a character device, not a regular file";
  if (S_ISBLK(mode)) return "is a block device, not a regular file";
  if (S_ISFIFO(mode)) return "is a FIFO (named pipe), not a regular file";
  if (S_ISSOCK(mode)) return "is a socket, not a regular file";
  return "is not a regular file";
}

/// "" if `st` is a regular file within kMaxFileBytes, else the reason.
std::string RegularFileProblem(const struct stat& st) {
  if (!S_ISREG(st.st_mode)) return FileType(st.st_mode);
  if (static_cast<std::uintmax_t>(st.st_size) > kMaxFileBytes) {
    return "the file has " + std::to_string(st.st_size) + " bytes (input files have at most " +
           std::to_string(kMaxFileBytes) + " bytes, 1 MiB)";
  }
  return "";
}

bool PlainScalar(const YAML::Node& node) {
  // yaml-cpp tags plain scalars "?" and quoted ones "!"; explicit numeric tags are fine.
  return node.IsScalar() && (node.Tag() == "?" || node.Tag() == "tag:yaml.org,2002:float" ||
                             node.Tag() == "tag:yaml.org,2002:int");
}

}  // namespace

YamlNode::YamlNode() : impl_(std::make_shared<const Impl>()) {}
YamlNode::YamlNode(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
YamlNode::~YamlNode() = default;
YamlNode::YamlNode(const YamlNode&) = default;
YamlNode& YamlNode::operator=(const YamlNode&) = default;

bool YamlNode::IsPlainScalar() const { return PlainScalar(impl_->node); }

std::string YamlNode::Scalar() const {
  return impl_->node.IsScalar() ? impl_->node.Scalar() : std::string();
}

std::string ReadTextFile(const std::string& path) {
  auto fail = [&path](const std::string& reason) {
    throw std::runtime_error(path + ": cannot read: " + reason);
  };
  // The type first, without opening: opening a FIFO with no writer would block.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) fail(std::strerror(errno));
  if (std::string problem = RegularFileProblem(st); !problem.empty()) fail(problem);
  // O_NONBLOCK: should the path have become a FIFO since, open does not wait for a writer;
  // fstat on the open file closes that race.
  int fd = -1;
  do {
    fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  } while (fd < 0 && errno == EINTR);
  if (fd < 0) fail(std::strerror(errno));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  if (::fstat(fd, &st) != 0) fail(std::strerror(errno));
  if (std::string problem = RegularFileProblem(st); !problem.empty()) fail(problem);
  // At most kMaxFileBytes + 1 bytes, whatever the file does meanwhile (it may grow).
  std::string text(kMaxFileBytes + 1, '\0');
  std::size_t got = 0;
  while (got < text.size()) {
    const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(std::strerror(errno));
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  if (got > kMaxFileBytes) {
    fail("the file has more than " + std::to_string(kMaxFileBytes) +
         " bytes (input files have at most " + std::to_string(kMaxFileBytes) + " bytes, 1 MiB)");
  }
  text.resize(got);
  text.shrink_to_fit();
  return text;
}

std::string ShortValue(const std::string& value, std::size_t max_bytes) {
  if (value.size() <= max_bytes) return Escaped(value);
  return Escaped(value.substr(0, Utf8Prefix(value, max_bytes))) + "... (" +
         std::to_string(value.size()) + " bytes)";
}

std::string ShortList(const std::vector<std::string>& names) {
  constexpr std::size_t kMaxListed = 10;
  std::string s;
  for (std::size_t i = 0; i < names.size() && i < kMaxListed; ++i) {
    s += (i ? ", " : "") + ShortValue(names[i]);
  }
  if (names.size() > kMaxListed) s += ", ... (" + std::to_string(names.size()) + " in all)";
  return s;
}

std::string NameProblem(const std::string& name) {
  if (name.empty()) return "must not be empty";
  if (name.size() > kMaxNameBytes) {
    return "a name has at most " + std::to_string(kMaxNameBytes) + " bytes (this one has " +
           std::to_string(name.size()) + ")";
  }
  for (std::size_t i = 0; i < name.size(); ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    const bool nel = c == 0xC2 && i + 1 < name.size() && name[i + 1] == '\x85';
    if (c < 0x20 || c == 0x7F || nel) {
      return "a name must not contain control characters (tab, line breaks)";
    }
  }
  return "";
}

std::string Render(const YamlNode& value) {
  std::string s;
  RenderInto(Y(value), 0, s);
  // A scalar is already short (ShortValue); a collection is cut here.
  if (!Y(value).IsScalar() && s.size() > kMaxRenderedLength)
    s = s.substr(0, Utf8Prefix(s, kMaxRenderedLength - 3)) + "...";
  // One line: newlines of block scalars become visible escapes.
  return Escaped(s);
}

YamlDocument::YamlDocument(std::string path, std::string text)
    : YamlDocument(path, std::move(text), std::filesystem::path(path).parent_path().string()) {}

YamlDocument::YamlDocument(std::string path, std::string text, std::string base_dir)
    : path_(std::move(path)), text_(std::move(text)), base_dir_(std::move(base_dir)) {
  if (text_.size() > kMaxFileBytes) {
    throw std::invalid_argument(path_ + ": the text has " + std::to_string(text_.size()) +
                                " bytes (input files have at most " +
                                std::to_string(kMaxFileBytes) + " bytes, 1 MiB)");
  }
  // YAML streams are Unicode: refuse bytes that are not UTF-8 text before yaml-cpp sees
  // them (it would pass them on into names, and so into HDF5 strings declared UTF-8).
  if (const std::optional<TextFault> fault = CheckText(text_)) {
    const auto begin = text_.begin();
    const auto at = begin + static_cast<std::ptrdiff_t>(fault->offset);
    const std::size_t line = static_cast<std::size_t>(std::count(begin, at, '\n')) + 1;
    throw std::invalid_argument(path_ + ": line " + std::to_string(line) + ", byte offset " +
                                std::to_string(fault->offset) + ": " + fault->rule);
  }
  const YAML::Node root = ParseOneDocument(path_, text_);
  if (!root.IsDefined() || root.IsNull()) {
    throw std::invalid_argument(path_ + ": the file is empty (expected a YAML mapping)");
  }
  root_ = Wrap(root);
  if (!root.IsMap()) {
    throw std::invalid_argument(path_ + ": top level = " + Render(root_) +
                                ": expected a mapping of keys to values");
  }
}

void YamlDocument::Fail(const std::string& key,
                        const YamlNode& value,
                        const std::string& rule) const {
  throw std::invalid_argument(path_ + ": " + key + " = " + Render(value) + ": " + rule);
}

void YamlDocument::Fail(const std::string& key, const std::string& rule) const {
  throw std::invalid_argument(path_ + ": " + key + ": " + rule);
}

std::string JoinKey(const std::string& parent, const std::string& key) {
  const std::string shown = ShortValue(key);  // keys from files may be long or hold a '\n'
  return parent.empty() ? shown : parent + "." + shown;
}

std::vector<std::pair<std::string, YamlNode>> MappingEntries(const YamlDocument& doc,
                                                             const YamlNode& value,
                                                             const std::string& path) {
  const YAML::Node& node = Y(value);
  if (!node.IsMap()) doc.Fail(path, value, "expected a mapping (key: value entries)");
  std::vector<std::pair<std::string, YamlNode>> entries;
  // Duplicates by hash: a mapping may have ~kMaxNodes / 2 keys (a pairwise check of 50,000
  // keys took seconds).
  std::unordered_map<std::string, std::size_t> seen;
  for (const auto& kv : node) {
    if (!kv.first.IsScalar()) {
      doc.Fail(JoinKey(path, Render(Wrap(kv.first))), Wrap(kv.second),
               "keys must be plain strings");
    }
    const std::string key = kv.first.Scalar();
    const auto [it, inserted] = seen.emplace(key, entries.size());
    if (!inserted) {
      const YamlNode& first = entries[it->second].second;
      doc.Fail(
          JoinKey(path, key), Wrap(kv.second),
          "duplicate key (first given on line " + std::to_string(Y(first).Mark().line + 1) + ")");
    }
    entries.emplace_back(key, Wrap(kv.second));
  }
  return entries;
}

std::vector<YamlNode> SequenceElements(const YamlDocument& doc,
                                       const YamlNode& value,
                                       const std::string& path,
                                       const std::string& what) {
  const YAML::Node& node = Y(value);
  if (!node.IsSequence()) doc.Fail(path, value, "expected a sequence of " + what);
  std::vector<YamlNode> elements;
  for (const YAML::Node& e : node) elements.push_back(Wrap(e));
  return elements;
}

double ReadNumber(const YamlDocument& doc, const YamlNode& given, const std::string& path) {
  const YAML::Node& node = Y(given);
  if (node.IsScalar() && node.Tag() == "!") {
    doc.Fail(path, given, "expected a number, not a quoted string");
  }
  double value = 0.0;
  if (!PlainScalar(node) || !YAML::convert<double>::decode(node, value)) {
    doc.Fail(path, given, "expected a number");
  }
  if (!std::isfinite(value)) doc.Fail(path, given, "must be finite");
  return value;
}

std::string ReadText(const YamlDocument& doc, const YamlNode& given, const std::string& path) {
  const YAML::Node& node = Y(given);
  if (!node.IsScalar()) doc.Fail(path, given, "expected a string");
  return node.Scalar();
}

bool ReadBool(const YamlDocument& doc, const YamlNode& given, const std::string& path) {
  const YAML::Node& node = Y(given);
  bool value = false;
  if (!PlainScalar(node) && !(node.IsScalar() && node.Tag() == "tag:yaml.org,2002:bool")) {
    doc.Fail(path, given, "expected true or false");
  }
  if (!YAML::convert<bool>::decode(node, value)) doc.Fail(path, given, "expected true or false");
  return value;
}

Eigen::VectorXd ReadNumbers(const YamlDocument& doc,
                            const YamlNode& value,
                            const std::string& path,
                            int size) {
  const std::string what = size >= 0 ? std::to_string(size) + " numbers" : "numbers";
  const std::vector<YamlNode> elements = SequenceElements(doc, value, path, what);
  if (size >= 0 && elements.size() != static_cast<std::size_t>(size)) {
    doc.Fail(path, value,
             "must have " + std::to_string(size) + " elements (has " +
                 std::to_string(elements.size()) + ")");
  }
  Eigen::VectorXd v(static_cast<Eigen::Index>(elements.size()));
  for (std::size_t i = 0; i < elements.size(); ++i) {
    v[static_cast<Eigen::Index>(i)] =
        ReadNumber(doc, elements[i], path + "[" + std::to_string(i) + "]");
  }
  return v;
}

math::Mat3 ReadMatrix3(const YamlDocument& doc, const YamlNode& value, const std::string& path) {
  const std::vector<YamlNode> rows = SequenceElements(doc, value, path, "3 rows of 3 numbers");
  if (rows.size() != 3) {
    doc.Fail(path, value,
             "must have 3 rows of 3 numbers (has " + std::to_string(rows.size()) + " rows)");
  }
  math::Mat3 M;
  for (int i = 0; i < 3; ++i) {
    M.row(i) = ReadNumbers(doc, rows[i], path + "[" + std::to_string(i) + "]", 3).transpose();
  }
  return M;
}

Fields::Fields(const YamlDocument& doc,
               const YamlNode& node,
               std::string path,
               const std::vector<std::string>& allowed)
    : doc_(&doc), node_(node), path_(std::move(path)), entries_(MappingEntries(doc, node, path_)) {
  for (const auto& [key, value] : entries_) {
    bool known = false;
    for (const std::string& a : allowed) known = known || a == key;
    if (!known) doc.Fail(Key(key), value, "unknown key (allowed: " + Join(allowed) + ")");
  }
}

const YamlNode* Fields::Find(const std::string& key) const {
  for (const auto& kv : entries_) {
    if (kv.first == key) return &kv.second;
  }
  return nullptr;
}

bool Fields::Has(const std::string& key) const { return Find(key) != nullptr; }

const YamlNode& Fields::Get(const std::string& key) const {
  const YamlNode* n = Find(key);
  if (n == nullptr) doc_->Fail(Key(key), "required key is missing");
  return *n;
}

double Fields::Number(const std::string& key) const {
  return ReadNumber(*doc_, Get(key), Key(key));
}

std::optional<double> Fields::OptionalNumber(const std::string& key) const {
  if (!Has(key)) return std::nullopt;
  return Number(key);
}

double Fields::Degrees(const std::string& key) const { return Number(key) * kRadiansPerDegree; }

std::optional<double> Fields::OptionalDegrees(const std::string& key) const {
  if (!Has(key)) return std::nullopt;
  return Degrees(key);
}

std::string Fields::Text(const std::string& key) const {
  return ReadText(*doc_, Get(key), Key(key));
}

std::string Fields::Name(const std::string& key) const {
  std::string name = Text(key);
  if (const std::string problem = NameProblem(name); !problem.empty()) Fail(key, problem);
  return name;
}

std::optional<std::string> Fields::OptionalText(const std::string& key) const {
  if (!Has(key)) return std::nullopt;
  return Text(key);
}

std::optional<bool> Fields::OptionalBool(const std::string& key) const {
  if (!Has(key)) return std::nullopt;
  return ReadBool(*doc_, Get(key), Key(key));
}

Eigen::VectorXd Fields::Numbers(const std::string& key, int size) const {
  return ReadNumbers(*doc_, Get(key), Key(key), size);
}

math::Vec3 Fields::Vector3(const std::string& key) const {
  const Eigen::VectorXd v = Numbers(key, 3);
  return math::Vec3(v[0], v[1], v[2]);
}

math::Mat3 Fields::Matrix3(const std::string& key) const {
  return ReadMatrix3(*doc_, Get(key), Key(key));
}

Fields Fields::Mapping(const std::string& key, const std::vector<std::string>& allowed) const {
  return Fields(*doc_, Get(key), Key(key), allowed);
}

std::string Fields::FilePath(const std::string& key) const {
  const std::string relative = Text(key);
  if (relative.empty()) Fail(key, "must name a file");
  const std::filesystem::path resolved =
      (std::filesystem::path(doc_->base_dir()) / relative).lexically_normal();
  // Checked without opening (a FIFO would block): the reader (ReadTextFile) checks again.
  std::string problem;
  struct stat st {};
  if (::stat(resolved.c_str(), &st) != 0) {
    problem = std::strerror(errno);
  } else if (::access(resolved.c_str(), R_OK) != 0) {
    problem = std::strerror(errno);
  } else {
    problem = RegularFileProblem(st);
  }
  if (!problem.empty()) {
    throw std::runtime_error(doc_->path() + ": " + Key(key) + " = " +
                             ShortValue(relative, kMaxShownPathBytes) + ": cannot read " +
                             ShortValue(resolved.string(), kMaxShownPathBytes) + ": " + problem);
  }
  return resolved.string();
}

void Fields::Fail(const std::string& key, const std::string& rule) const {
  doc_->Fail(Key(key), Get(key), rule);
}

void Fields::RequireExactlyOne(const std::string& a, const std::string& b) const {
  (void)RequireExactlyOne(std::vector<std::string>{a, b});
}

std::string Fields::RequireExactlyOne(const std::vector<std::string>& keys) const {
  std::vector<std::string> given;
  std::string all;
  for (const std::string& k : keys) {
    if (Has(k)) given.push_back(k);
    all += (all.empty() ? "" : ", ") + k;
  }
  if (given.size() == 1) return given.front();
  std::string why;
  if (given.empty()) {
    why = keys.size() == 2 ? "neither is given" : "none is given";
  } else if (given.size() == 2 && keys.size() == 2) {
    why = "both are given";
  } else {
    for (const std::string& k : given) why += (why.empty() ? "" : ", ") + k;
    why += " are given";
  }
  doc_->Fail(path_.empty() ? "top level" : path_, node_,
             "exactly one of " + all + " is required (" + why + ")");
}

}  // namespace deploysim::io::yaml
