#include "deploysim/io/yaml_fields.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace deploysim::io::internal {

namespace {

constexpr std::size_t kMaxRenderedLength = 80;

std::string Join(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

std::string RenderUnbounded(const YAML::Node& node) {
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
        s += (i ? ", " : "") + RenderUnbounded(node[i]);
        if (s.size() > kMaxRenderedLength) break;
      }
      return s + "]";
    }
    case YAML::NodeType::Map: {
      std::string s = "{";
      bool first = true;
      for (const auto& kv : node) {
        s += (first ? "" : ", ") + RenderUnbounded(kv.first) + ": " + RenderUnbounded(kv.second);
        first = false;
        if (s.size() > kMaxRenderedLength) break;
      }
      return s + "}";
    }
  }
  return "?";
}

bool IsPlainScalar(const YAML::Node& node) {
  // yaml-cpp tags plain scalars "?" and quoted ones "!"; explicit numeric tags are fine.
  return node.IsScalar() && (node.Tag() == "?" || node.Tag() == "tag:yaml.org,2002:float" ||
                             node.Tag() == "tag:yaml.org,2002:int");
}

}  // namespace

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

std::string Render(const YAML::Node& node) {
  std::string s = RenderUnbounded(node);
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
  root_ = docs.front();
  if (!root_.IsMap()) {
    throw std::invalid_argument(path_ + ": top level = " + Render(root_) +
                                ": expected a mapping of keys to values");
  }
}

void YamlDocument::Fail(const std::string& key,
                        const YAML::Node& value,
                        const std::string& rule) const {
  throw std::invalid_argument(path_ + ": " + key + " = " + Render(value) + ": " + rule);
}

void YamlDocument::Fail(const std::string& key, const std::string& rule) const {
  throw std::invalid_argument(path_ + ": " + key + ": " + rule);
}

std::string JoinKey(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::vector<std::pair<std::string, YAML::Node>> MappingEntries(const YamlDocument& doc,
                                                               const YAML::Node& node,
                                                               const std::string& path) {
  if (!node.IsMap()) doc.Fail(path, node, "expected a mapping (key: value entries)");
  std::vector<std::pair<std::string, YAML::Node>> entries;
  for (const auto& kv : node) {
    if (!kv.first.IsScalar()) {
      doc.Fail(JoinKey(path, Render(kv.first)), kv.second, "keys must be plain strings");
    }
    const std::string key = kv.first.Scalar();
    for (const auto& [seen, value] : entries) {
      if (seen == key) {
        doc.Fail(
            JoinKey(path, key), kv.second,
            "duplicate key (first given on line " + std::to_string(value.Mark().line + 1) + ")");
      }
    }
    entries.emplace_back(key, kv.second);
  }
  return entries;
}

std::vector<YAML::Node> SequenceElements(const YamlDocument& doc,
                                         const YAML::Node& node,
                                         const std::string& path,
                                         const std::string& what) {
  if (!node.IsSequence()) doc.Fail(path, node, "expected a sequence of " + what);
  std::vector<YAML::Node> elements;
  for (const YAML::Node& e : node) elements.push_back(e);
  return elements;
}

double ReadNumber(const YamlDocument& doc, const YAML::Node& node, const std::string& path) {
  if (node.IsScalar() && node.Tag() == "!") {
    doc.Fail(path, node, "expected a number, not a quoted string");
  }
  double value = 0.0;
  if (!IsPlainScalar(node) || !YAML::convert<double>::decode(node, value)) {
    doc.Fail(path, node, "expected a number");
  }
  if (!std::isfinite(value)) doc.Fail(path, node, "must be finite");
  return value;
}

std::string ReadText(const YamlDocument& doc, const YAML::Node& node, const std::string& path) {
  if (!node.IsScalar()) doc.Fail(path, node, "expected a string");
  return node.Scalar();
}

bool ReadBool(const YamlDocument& doc, const YAML::Node& node, const std::string& path) {
  bool value = false;
  if (!IsPlainScalar(node) && !(node.IsScalar() && node.Tag() == "tag:yaml.org,2002:bool")) {
    doc.Fail(path, node, "expected true or false");
  }
  if (!YAML::convert<bool>::decode(node, value)) doc.Fail(path, node, "expected true or false");
  return value;
}

Eigen::VectorXd ReadNumbers(const YamlDocument& doc,
                            const YAML::Node& node,
                            const std::string& path,
                            int size) {
  const std::string what = size >= 0 ? std::to_string(size) + " numbers" : "numbers";
  const std::vector<YAML::Node> elements = SequenceElements(doc, node, path, what);
  if (size >= 0 && elements.size() != static_cast<std::size_t>(size)) {
    doc.Fail(path, node,
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

math::Mat3 ReadMatrix3(const YamlDocument& doc, const YAML::Node& node, const std::string& path) {
  const std::vector<YAML::Node> rows = SequenceElements(doc, node, path, "3 rows of 3 numbers");
  if (rows.size() != 3) {
    doc.Fail(path, node,
             "must have 3 rows of 3 numbers (has " + std::to_string(rows.size()) + " rows)");
  }
  math::Mat3 M;
  for (int i = 0; i < 3; ++i) {
    M.row(i) = ReadNumbers(doc, rows[i], path + "[" + std::to_string(i) + "]", 3).transpose();
  }
  return M;
}

Fields::Fields(const YamlDocument& doc,
               const YAML::Node& node,
               std::string path,
               const std::vector<std::string>& allowed)
    : doc_(&doc), node_(node), path_(std::move(path)), entries_(MappingEntries(doc, node, path_)) {
  for (const auto& [key, value] : entries_) {
    bool known = false;
    for (const std::string& a : allowed) known = known || a == key;
    if (!known) doc.Fail(Key(key), value, "unknown key (allowed: " + Join(allowed) + ")");
  }
}

const YAML::Node* Fields::Find(const std::string& key) const {
  for (const auto& kv : entries_) {
    if (kv.first == key) return &kv.second;
  }
  return nullptr;
}

bool Fields::Has(const std::string& key) const { return Find(key) != nullptr; }

const YAML::Node& Fields::Get(const std::string& key) const {
  const YAML::Node* n = Find(key);
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

}  // namespace deploysim::io::internal
