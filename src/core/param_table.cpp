#include <action_flow/param_table.h>

#include <action_flow/files.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace action_flow
{
namespace
{
// "[a, b, c]" (or a bare "a, b") into its items; "[]" into none.
std::vector<std::string> listItems(const std::string& text)
{
  std::string t = trimmed(text);
  if (t.size() >= 2 && t.front() == '[' && t.back() == ']')
    t = t.substr(1, t.size() - 2);
  std::vector<std::string> out;
  if (trimmed(t).empty())
    return out;
  std::stringstream ss(t);
  std::string item;
  while (std::getline(ss, item, ','))
    out.push_back(trimmed(item));
  return out;
}

template <class T>
std::string joinList(const T& items, int n)
{
  std::string out = "[";
  for (int i = 0; i < n; ++i)
    out += (i ? ", " : "") + paramText(items[i]);
  return out + "]";
}

double parseNumber(const std::string& text)
{
  const std::string t = trimmed(text);
  std::size_t used = 0;
  double v = 0;
  try
  {
    v = std::stod(t, &used);
  }
  catch (const std::exception&)
  {
    used = 0;
  }
  if (t.empty() || used != t.size() || !std::isfinite(v))
    throw std::invalid_argument("expected a finite number, got '" + text + "'");
  return v;
}

template <int N>
Eigen::Matrix<float, N, 1> parseVector(const std::string& text)
{
  const auto items = listItems(text);
  if (items.size() != static_cast<std::size_t>(N))
    throw std::invalid_argument("expected a list of " + std::to_string(N) + " numbers, got '" + text + "'");
  Eigen::Matrix<float, N, 1> v;
  for (int i = 0; i < N; ++i)
    v[i] = static_cast<float>(parseNumber(items[static_cast<std::size_t>(i)]));
  return v;
}
}  // namespace

std::string paramText(int v)
{
  return std::to_string(v);
}
// The shortest text that reads back as the same value (0.3f is "0.3", not "0.300000012").
template <class T>
std::string shortestText(T v, int max_digits)
{
  char buf[40];
  for (int digits = 6;; ++digits)
  {
    std::snprintf(buf, sizeof(buf), "%.*g", digits, static_cast<double>(v));
    if (digits >= max_digits || static_cast<T>(std::strtod(buf, nullptr)) == v)
      return buf;
  }
}
std::string paramText(float v)
{
  return shortestText(v, 9);
}
std::string paramText(double v)
{
  return shortestText(v, 17);
}
std::string paramText(bool v)
{
  return v ? "true" : "false";
}
std::string paramText(const std::string& v)
{
  return v;
}
std::string paramText(const std::vector<std::string>& v)
{
  return joinList(v, static_cast<int>(v.size()));
}
std::string paramText(const Eigen::Vector3f& v)
{
  return joinList(v, 3);
}
std::string paramText(const std::optional<Eigen::Vector4f>& v)
{
  return v ? joinList(*v, 4) : "[]";
}

void parseParam(const std::string& text, int& v)
{
  const double d = parseNumber(text);
  if (d != std::floor(d) || std::fabs(d) > 2e9)
    throw std::invalid_argument("expected a whole number, got '" + text + "'");
  v = static_cast<int>(d);
}
void parseParam(const std::string& text, float& v)
{
  v = static_cast<float>(parseNumber(text));
}
void parseParam(const std::string& text, double& v)
{
  v = parseNumber(text);
}
void parseParam(const std::string& text, bool& v)
{
  const std::string t = trimmed(text);
  if (t == "true" || t == "True" || t == "1")
    v = true;
  else if (t == "false" || t == "False" || t == "0")
    v = false;
  else
    throw std::invalid_argument("expected true or false, got '" + text + "'");
}
void parseParam(const std::string& text, std::string& v)
{
  v = text;
}
void parseParam(const std::string& text, std::vector<std::string>& v)
{
  v = listItems(text);
}
void parseParam(const std::string& text, Eigen::Vector3f& v)
{
  v = parseVector<3>(text);
}
void parseParam(const std::string& text, std::optional<Eigen::Vector4f>& v)
{
  if (listItems(text).empty())
    v.reset();
  else
    v = parseVector<4>(text);
}

int parseChoice(const std::string& text, const std::vector<std::string>& names)
{
  std::string expected;
  for (std::size_t i = 0; i < names.size(); ++i)
  {
    if (trimmed(text) == names[i])
      return static_cast<int>(i);
    expected += (i ? (i + 1 == names.size() ? " or " : ", ") : "") + names[i];
  }
  throw std::invalid_argument("expected " + expected + ", got '" + text + "'");
}

std::string stableHash(const std::string& text)
{
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a 64: offset basis, prime below
  for (unsigned char c : text)
    h = (h ^ c) * 1099511628211ull;
  char buf[17];
  std::snprintf(buf, sizeof(buf), "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace action_flow
