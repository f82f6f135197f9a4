#include "deploysim/io/yaml_fields.h"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

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
// (`a: &a [*a]`) would otherwise make endless.
constexpr int kMaxRenderedDepth = 8;

std::string RenderUnbounded(const YAML::Node& node, int depth = 0) {
  if (depth > kMaxRenderedDepth) return "...";
  switch (node.Type()) {
    case YAML::NodeType::Undefined:
    case YAML::NodeType::Null:
      return "null";
    case YAML::NodeType::Scalar:
      // Quoted scalars keep their quotes, so that `"60"` reads as the string it is.
      return node.Tag() == "!" ? "\"" + node.Scalar() + "\"" : node.Scalar();
    case YAML::NodeType::Sequence: {
      std::string s = "[";
      for (std::size_t i = 0; i < node.size(); ++i) {
        s += (i ? ", " : "") + RenderUnbounded(node[i], depth + 1);
        if (s.size() > kMaxRenderedLength) break;
      }
      return s + "]";
    }
    case YAML::NodeType::Map: {
      std::string s = "{";
      bool first = true;
      for (const auto& kv : node) {
        s += (first ? "" : ", ") + RenderUnbounded(kv.first, depth + 1) + ": " +
             RenderUnbounded(kv.second, depth + 1);
        first = false;
        if (s.size() > kMaxRenderedLength) break;
      }
      return s + "}";
    }
  }
  return "?";
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
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw std::runtime_error(path + ": cannot read: is a directory");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot read: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw std::runtime_error(path + ": cannot read: " + std::strerror(errno));
  return text.str();
}

std::string Render(const YamlNode& value) {
  std::string s = RenderUnbounded(Y(value));
  if (s.size() > kMaxRenderedLength) s = s.substr(0, kMaxRenderedLength - 3) + "...";
  // One line: newlines of block scalars become visible escapes.
  std::string out;
  for (char c : s) out += (c == '\n') ? std::string("\\n") : std::string(1, c);
  return out;
}

YamlDocument::YamlDocument(std::string path, std::string text)
    : path_(std::move(path)), text_(std::move(text)) {
  std::vector<YAML::Node> docs;
  // yaml-cpp reports syntax errors by exception; translate them to this module's
  // one-line format (the only place io handles a third-party parser error).
  try {
    docs = YAML::LoadAll(text_);
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument(path_ + ": line " + std::to_string(e.mark.line + 1) + ", column " +
                                std::to_string(e.mark.column + 1) +
                                ": YAML syntax error: " + e.msg);
  }
  if (docs.empty() || docs.front().IsNull()) {
    throw std::invalid_argument(path_ + ": the file is empty (expected a YAML mapping)");
  }
  if (docs.size() > 1) {
    throw std::invalid_argument(path_ + ": " + std::to_string(docs.size()) +
                                " YAML documents ('---'): one document per file");
  }
  root_ = Wrap(docs.front());
  if (!docs.front().IsMap()) {
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
  return parent.empty() ? key : parent + "." + key;
}

std::vector<std::pair<std::string, YamlNode>> MappingEntries(const YamlDocument& doc,
                                                             const YamlNode& value,
                                                             const std::string& path) {
  const YAML::Node& node = Y(value);
  if (!node.IsMap()) doc.Fail(path, value, "expected a mapping (key: value entries)");
  std::vector<std::pair<std::string, YamlNode>> entries;
  for (const auto& kv : node) {
    if (!kv.first.IsScalar()) {
      doc.Fail(JoinKey(path, Render(Wrap(kv.first))), Wrap(kv.second),
               "keys must be plain strings");
    }
    const std::string key = kv.first.Scalar();
    for (const auto& [seen, first] : entries) {
      if (seen == key) {
        doc.Fail(
            JoinKey(path, key), Wrap(kv.second),
            "duplicate key (first given on line " + std::to_string(Y(first).Mark().line + 1) + ")");
      }
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

std::string Fields::Text(const std::string& key) const {
  return ReadText(*doc_, Get(key), Key(key));
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
      (std::filesystem::path(doc_->path()).parent_path() / relative).lexically_normal();
  std::error_code ec;
  const bool is_dir = std::filesystem::is_directory(resolved, ec);
  std::ifstream probe(resolved);
  if (is_dir || !probe) {
    throw std::runtime_error(doc_->path() + ": " + Key(key) + " = " + relative + ": cannot read " +
                             resolved.string() + ": " +
                             (is_dir ? std::string("is a directory") : std::strerror(errno)));
  }
  return resolved.string();
}

void Fields::Fail(const std::string& key, const std::string& rule) const {
  doc_->Fail(Key(key), Get(key), rule);
}

void Fields::RequireExactlyOne(const std::string& a, const std::string& b) const {
  const bool has_a = Has(a);
  const bool has_b = Has(b);
  if (has_a && has_b) {
    doc_->Fail(path_.empty() ? "top level" : path_, node_,
               "exactly one of " + a + ", " + b + " is required (both are given)");
  }
  if (!has_a && !has_b) {
    doc_->Fail(path_.empty() ? "top level" : path_, node_,
               "exactly one of " + a + ", " + b + " is required (neither is given)");
  }
}

}  // namespace deploysim::io::yaml
