// The dashboard's own request and response: what the listener (http_server) parsed and what the
// routes (api) answer, independent of the HTTP library underneath.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace tessera::server {

using HttpFields = std::vector<std::pair<std::string, std::string>>;

struct HttpRequest {
  std::string method;  ///< "GET", "POST", ... as sent
  std::string path;    ///< the target before '?', percent-decoded ('+' kept)
  HttpFields params;   ///< the query's name=value pairs, decoded ('+' is a space), in order
  HttpFields headers;  ///< as sent; names compare case-insensitively
  std::string body;    ///< read only for requests that carry one (POST, PUT, PATCH, DELETE)
  std::string remote_address;        ///< the peer's IP address ("127.0.0.1", "::1")
  std::vector<std::string> matches;  ///< the route's captures: [0] the path, [1] the first group

  /// The first header named `name` (any case); "" when there is none.
  std::string header(std::string_view name) const;
  bool has_header(std::string_view name) const;
  /// The first query parameter named `name` (exact case); "" when there is none.
  std::string param(std::string_view name) const;
  bool has_param(std::string_view name) const;
};

struct HttpResponse {
  int status = 200;
  HttpFields headers;  ///< besides Content-Type and Content-Length, which the listener writes
  std::string body;
  std::string content_type;  ///< "" for no body

  /// Replaces any header of that name (any case).
  void set_header(std::string_view name, std::string value);
  void set_content(std::string content, std::string type) {
    body = std::move(content);
    content_type = std::move(type);
  }
};

/// Percent-decodes `text` ("%2F" is '/'); with `plus_is_space`, '+' is a space (query strings).
/// A '%' not followed by two hex digits stays as it is.
std::string percent_decode(std::string_view text, bool plus_is_space);

/// Splits a request target into the decoded path and query parameters.
void split_target(std::string_view target, std::string& path, HttpFields& params);

/// Sets `res` to the JSON {"error": message} with `status` and Cache-Control: no-store: every
/// error of the dashboard has this form.
void set_json_error(HttpResponse& res, int status, const std::string& message);

}  // namespace tessera::server
