#include "dashboard/http_message.h"

#include <strings.h>

#include <algorithm>
#include <nlohmann/json.hpp>

namespace tessera::server {
namespace {

bool http_names_equal(std::string_view a, std::string_view b) {
  return a.size() == b.size() && strncasecmp(a.data(), b.data(), a.size()) == 0;
}

int http_hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

const std::pair<std::string, std::string>* http_find(const HttpFields& fields,
                                                     std::string_view name, bool any_case) {
  auto it = std::find_if(fields.begin(), fields.end(), [&](const auto& field) {
    return any_case ? http_names_equal(field.first, name) : field.first == name;
  });
  return it == fields.end() ? nullptr : &*it;
}

}  // namespace

std::string HttpRequest::header(std::string_view name) const {
  const auto* field = http_find(headers, name, true);
  return field ? field->second : std::string();
}

bool HttpRequest::has_header(std::string_view name) const {
  return http_find(headers, name, true) != nullptr;
}

std::string HttpRequest::param(std::string_view name) const {
  const auto* field = http_find(params, name, false);
  return field ? field->second : std::string();
}

bool HttpRequest::has_param(std::string_view name) const {
  return http_find(params, name, false) != nullptr;
}

void HttpResponse::set_header(std::string_view name, std::string value) {
  std::erase_if(headers, [&](const auto& field) { return http_names_equal(field.first, name); });
  headers.emplace_back(std::string(name), std::move(value));
}

std::string percent_decode(std::string_view text, bool plus_is_space) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '%' && i + 2 < text.size() && http_hex_value(text[i + 1]) >= 0 &&
        http_hex_value(text[i + 2]) >= 0) {
      out += char(http_hex_value(text[i + 1]) * 16 + http_hex_value(text[i + 2]));
      i += 2;
    } else if (c == '+' && plus_is_space) {
      out += ' ';
    } else {
      out += c;
    }
  }
  return out;
}

void split_target(std::string_view target, std::string& path, HttpFields& params) {
  const size_t question = target.find('?');
  path = percent_decode(target.substr(0, question), false);
  params.clear();
  if (question == std::string_view::npos) return;
  std::string_view query = target.substr(question + 1);
  while (!query.empty()) {
    const size_t amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    if (!pair.empty()) {
      const size_t eq = pair.find('=');
      params.emplace_back(percent_decode(pair.substr(0, eq), true),
                          eq == std::string_view::npos ? std::string()
                                                       : percent_decode(pair.substr(eq + 1), true));
    }
    if (amp == std::string_view::npos) break;
    query.remove_prefix(amp + 1);
  }
}

void set_json_error(HttpResponse& res, int status, const std::string& message) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  // The message may quote the request (its path): bytes that are not UTF-8 become U+FFFD rather
  // than failing the answer.
  const nlohmann::json body{{"error", message}};
  res.set_content(body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                  "application/json");
}

}  // namespace tessera::server
