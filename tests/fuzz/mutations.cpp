#include "tests/fuzz/mutations.h"

#include <algorithm>
#include <cctype>
#include <functional>
#include <map>
#include <utility>

#include <nlohmann/json.hpp>

namespace furnace::fuzz {

namespace {

using nlohmann::json;

// Placeholders spliced into the dumped text: a raw token where a JSON value
// cannot hold it, a key that an object cannot hold twice.
const std::string kValueMarker = "@@FUZZ_VALUE@@";
const std::string kKeyMarker = "@@FUZZ_KEY@@";

// Numbers at and beyond every edge: beyond double range (nlohmann refuses
// them while parsing), JSON's missing NaN/Infinity, zero and its sign,
// negative, beyond Embree's float range, denormal, integers beyond 64 bits.
const std::vector<std::string> kNumberTokens = {
    "1e309", "-1e309", "NaN", "Infinity", "\"nan\"", "0", "-0", "-1", "1e19", "-1e19",
    "1e-320", "1e300", "99999999999999999999", "2.5", "1e6", "-1e-7"};
// A value of each other type.
const std::vector<std::string> kTypeTokens = {"\"x\"", "\"\"", "[]", "{}", "true", "null", "[1, 2, 3]", "7"};

std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// `base` with the value at `pointer` written as the raw text `token`.
std::string with_token(json base, const json::json_pointer& pointer, const std::string& token) {
  base[pointer] = kValueMarker;
  return replace_once(base.dump(2), "\"" + kValueMarker + "\"", token);
}

std::vector<std::string> typos(const std::string& key) {
  std::vector<std::string> out;
  if (key.size() >= 2) {
    std::string dropped = key;
    dropped.erase(key.size() / 2, 1);
    out.push_back(dropped);
    std::string swapped = key;
    std::swap(swapped[0], swapped[1]);
    if (swapped != key) out.push_back(swapped);
  }
  std::string doubled = key;
  doubled.insert(doubled.size() / 2, 1, key[key.size() / 2]);
  out.push_back(doubled);
  std::string capital = key;
  capital[0] = char(std::toupper(static_cast<unsigned char>(capital[0])));
  if (capital != key) out.push_back(capital);
  return out;
}

// Calls visit(pointer, value) for every value of `j`, the root included.
void walk(const json& j, const json::json_pointer& at, const std::function<void(const json::json_pointer&, const json&)>& visit) {
  visit(at, j);
  if (j.is_object())
    for (const auto& item : j.items()) walk(item.value(), at / item.key(), visit);
  else if (j.is_array())
    for (size_t i = 0; i < j.size(); ++i) walk(j[i], at / i, visit);
}

}  // namespace

std::vector<SceneMutation> scene_mutations(const std::string& scene, const std::string& text) {
  std::vector<SceneMutation> out;
  const json base = json::parse(text);
  const auto add = [&](const std::string& kind, const std::string& what, std::string mutated) {
    out.push_back({scene, kind, scene + " " + what, std::move(mutated)});
  };
  walk(base, json::json_pointer(), [&](const json::json_pointer& p, const json& v) {
    const std::string where = p.to_string().empty() ? "/" : p.to_string();
    if (v.is_number())
      for (const std::string& t : kNumberTokens) add("number", where + " := " + t, with_token(base, p, t));
    if (!p.empty())
      for (const std::string& t : kTypeTokens) add("type", where + " := " + t, with_token(base, p, t));
    if (v.is_object()) {
      for (const auto& item : v.items()) {
        const std::string key = item.key();
        json deleted = base;
        deleted[p].erase(key);
        add("delete", where + " delete '" + key + "'", deleted.dump(2));
        for (const std::string& typo : typos(key)) {
          json renamed = base;
          renamed[p].erase(key);
          renamed[p][typo] = item.value();
          add("rename", where + " rename '" + key + "' -> '" + typo + "'", renamed.dump(2));
        }
        for (const json& value : {item.value(), json(0)}) {
          json duplicated = base;
          duplicated[p][kKeyMarker] = value;
          add("duplicate", where + " duplicate '" + key + "' = " + value.dump(),
              replace_once(duplicated.dump(2), "\"" + kKeyMarker + "\"", json(key).dump()));
        }
      }
      json extra = base;
      extra[p]["extra"] = 1;
      add("unknown", where + " add 'extra'", extra.dump(2));
    }
    if (v.is_array()) {
      if (!v.empty()) {
        json shorter = base;
        shorter[p].erase(shorter[p].size() - 1);
        add("array", where + " drop last", shorter.dump(2));
        json longer = base;
        longer[p].push_back(v.back());
        add("array", where + " repeat last", longer.dump(2));
      }
      json zero = base;
      zero[p].push_back(0);
      add("array", where + " append 0", zero.dump(2));
      json empty = base;
      empty[p] = json::array();
      add("array", where + " empty", empty.dump(2));
    }
  });
  // Truncations at eleven evenly spaced bytes and one byte short; the empty file.
  for (size_t i = 0; i <= 11; ++i) {
    const size_t at = i == 11 ? text.size() - 1 : text.size() * i / 11;
    add("truncate", "truncated to " + std::to_string(at) + " bytes", text.substr(0, at));
  }
  return out;
}

std::vector<SceneMutation> sample(const std::vector<SceneMutation>& all, size_t count, size_t skip, uint64_t seed) {
  // Per kind, a shuffled order (Fisher-Yates with the named seed).
  std::map<std::string, std::vector<size_t>> by_kind;
  for (size_t i = 0; i < all.size(); ++i) by_kind[all[i].kind].push_back(i);
  SplitMix64 rng(seed);
  for (auto& [kind, indices] : by_kind)
    for (size_t i = indices.size(); i > 1; --i) std::swap(indices[i - 1], indices[rng.below(i)]);
  // Round-robin over the kinds until `skip + count` are taken.
  std::vector<SceneMutation> out;
  size_t taken = 0;
  for (size_t round = 0; out.size() < count; ++round) {
    bool any = false;
    for (const auto& [kind, indices] : by_kind) {
      if (round >= indices.size()) continue;
      any = true;
      if (taken++ >= skip) out.push_back(all[indices[round]]);
      if (out.size() == count) break;
    }
    if (!any) break;
  }
  return out;
}

std::vector<CommandLine> command_mutations(const std::vector<std::string>& args,
                                           const std::vector<std::string>& bounding) {
  // Values beyond every option's range: NaN in its spellings, infinities,
  // negative, zero, beyond double and 64-bit range, empty, text, a list.
  static const std::vector<std::string> kValues = {"nan", "NaN", "-nan", "inf", "-inf", "-1", "0", "1e400",
                                                   "99999999999999999999999", "1e19", "1e-320", "", "abc",
                                                   "0x10", "1,2", "--"};
  const auto is_option = [](const std::string& a) { return a.size() > 1 && a[0] == '-' && !std::isdigit(a[1]); };
  std::vector<CommandLine> out;
  const auto joined = [](const std::vector<std::string>& a) {
    std::string s;
    for (const std::string& x : a) s += (s.empty() ? "" : " ") + shell_quote(x);
    return s;
  };
  for (size_t i = 1; i < args.size(); ++i) {
    if (!is_option(args[i])) continue;
    const std::string& option = args[i];
    const bool has_value = i + 1 < args.size() && !is_option(args[i + 1]);
    if (has_value) {
      for (const std::string& v : kValues) {
        std::vector<std::string> a = args;
        a[i + 1] = v;
        out.push_back({option + " := " + shell_quote(v), a, option});
      }
      std::vector<std::string> no_value = args;
      no_value.erase(no_value.begin() + long(i) + 1);
      no_value.push_back(option);  // last, so nothing follows it
      no_value.erase(no_value.begin() + long(i));
      out.push_back({option + " without its value", no_value, option});
    }
    if (std::find(bounding.begin(), bounding.end(), option) == bounding.end()) {
      std::vector<std::string> dropped = args;
      dropped.erase(dropped.begin() + long(i), dropped.begin() + long(i) + (has_value ? 2 : 1));
      out.push_back({"without " + option, dropped, option});
    }
    std::vector<std::string> repeated = args;
    repeated.insert(repeated.end(), args.begin() + long(i), args.begin() + long(i) + (has_value ? 2 : 1));
    out.push_back({option + " twice", repeated, option});
    std::vector<std::string> misspelt = args;
    misspelt[i] = option.substr(0, option.size() - 1);
    out.push_back({option + " misspelt", misspelt, misspelt[i]});
  }
  std::vector<std::string> unknown = args;
  unknown.insert(unknown.end(), {"--bogus", "1"});
  out.push_back({"unknown option --bogus", unknown, "--bogus"});
  std::vector<std::string> subcommand = args;
  subcommand[0] += "x";
  out.push_back({"unknown subcommand " + subcommand[0], subcommand, subcommand[0]});
  for (CommandLine& c : out) c.description = args[0] + ": " + c.description + " (" + joined(c.args) + ")";
  return out;
}

std::string shell_quote(const std::string& arg) {
  std::string q = "'";
  for (const char c : arg) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace furnace::fuzz
