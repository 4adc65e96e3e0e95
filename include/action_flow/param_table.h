/**
 * @file param_table.h
 * @brief Each parameter is declared once: a line in its struct's static visit() that gives its
 *        name, the member (whose initialiser is the default), a one-line doc and what it shapes.
 *        Everything else goes through that list: the nodelets' ROS parameters (ros/params.h),
 *        the tools' --config yaml files, the model file's save, load and check, the descriptor
 *        cache's key, and docs/parameters.md (`train --list-params`).
 *
 * A struct's visit(self, v) calls v(name, member, doc, shapes) for each of its parameters, in
 * order; self may be const. Names are the ROS ones (nested structs' with their "flow/" prefix). Values travel as text (paramText/parseParam), so ROS, yaml and the
 * model file share one parser and one set of error messages.
 */
#pragma once

#include <Eigen/Core>

#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace action_flow
{
/** @brief What a parameter shapes. */
enum class Shapes
{
  Frames,   ///< the frame descriptors: part of the cache key; a model made with another value is refused
  Model,    ///< the sequence descriptor or the classifier: trained into the model, which then rules
  Runtime   ///< only what is done at runtime with the labels (the classifier's policy)
};

/** @brief The names of an enum's values, in the enum's order (specialised beside each enum). */
template <class E>
struct EnumNames;

// ---- values as text: one format for ROS, yaml and the model file ----
std::string paramText(int v);
std::string paramText(float v);
std::string paramText(double v);
std::string paramText(bool v);
std::string paramText(const std::string& v);
std::string paramText(const std::vector<std::string>& v);
std::string paramText(const Eigen::Vector3f& v);
std::string paramText(const std::optional<Eigen::Vector4f>& v);
template <class E, class = std::enable_if_t<std::is_enum<E>::value>>
std::string paramText(E v)
{
  return EnumNames<E>::names[static_cast<int>(v)];
}

/** @brief Parses @p text into @p v. @throws std::invalid_argument saying what was expected. */
void parseParam(const std::string& text, int& v);
void parseParam(const std::string& text, float& v);
void parseParam(const std::string& text, double& v);
void parseParam(const std::string& text, bool& v);
void parseParam(const std::string& text, std::string& v);
void parseParam(const std::string& text, std::vector<std::string>& v);
void parseParam(const std::string& text, Eigen::Vector3f& v);
void parseParam(const std::string& text, std::optional<Eigen::Vector4f>& v);
/** @brief One of the names in @p names (the enum's order); @throws std::invalid_argument otherwise. */
int parseChoice(const std::string& text, const std::vector<std::string>& names);
template <class E, class = std::enable_if_t<std::is_enum<E>::value>>
void parseParam(const std::string& text, E& v)
{
  v = static_cast<E>(parseChoice(text, std::vector<std::string>(std::begin(EnumNames<E>::names),
                                                                std::end(EnumNames<E>::names))));
}

/** @brief A value's type as the docs name it: int, float, bool, string, list, xyz, plane, or a|b|c. */
inline const char* paramType(int) { return "int"; }
inline const char* paramType(float) { return "float"; }
inline const char* paramType(double) { return "float"; }
inline const char* paramType(bool) { return "bool"; }
inline const char* paramType(const std::string&) { return "string"; }
inline const char* paramType(const std::vector<std::string>&) { return "list of strings"; }
inline const char* paramType(const Eigen::Vector3f&) { return "[x, y, z]"; }
inline const char* paramType(const std::optional<Eigen::Vector4f>&) { return "[a, b, c, d] or []"; }
template <class E, class = std::enable_if_t<std::is_enum<E>::value>>
std::string paramType(E)
{
  std::string out;
  for (const char* n : EnumNames<E>::names)
    out += (out.empty() ? "" : "|") + std::string(n);
  return out;
}

/** @brief One parameter as text. */
struct ParamEntry
{
  std::string name, value, type, doc;
  Shapes shapes;
};

/** @brief Every parameter of @p p (a struct with a static visit()), in declaration order. */
template <class P>
std::vector<ParamEntry> paramEntries(const P& p)
{
  std::vector<ParamEntry> out;
  P::visit(p, [&](const std::string& name, const auto& value, const char* doc, Shapes shapes) {
    out.push_back({ name, paramText(value), paramType(value), doc, shapes });
  });
  return out;
}

/**
 * @brief Sets parameter @p name of @p p from @p text.
 * @return false if @p p has no parameter of that name
 * @throws std::invalid_argument "<name>: <what was wrong>" if @p text does not parse
 */
template <class P>
bool setParam(P& p, const std::string& name, const std::string& text)
{
  bool found = false;
  P::visit(p, [&](const std::string& n, auto& value, const char*, Shapes) {
    if (found || n != name)
      return;
    found = true;
    try
    {
      parseParam(text, value);
    }
    catch (const std::invalid_argument& e)
    {
      throw std::invalid_argument(name + ": " + e.what());
    }
  });
  return found;
}

/** @brief A stable 64-bit hash (FNV-1a) as 16 hex digits: the same text gives the same key in every build. */
std::string stableHash(const std::string& text);

}  // namespace action_flow
