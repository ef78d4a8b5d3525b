// The viewer's page (HTML, CSS, plain JavaScript), compiled into the binary from apps/pbs/view/page by
// cmake/embed_page.cmake: no file is read and nothing is downloaded at run time.
#pragma once

#include <span>
#include <string_view>

namespace pbs::cli {

struct PageFile {
  std::string_view path;  // as requested: "/", "/view.js", …
  std::string_view type;  // its Content-Type
  std::string_view content;
};

std::span<const PageFile> viewPageFiles();

}  // namespace pbs::cli
