#pragma once
// XML text: the escapes of the five characters XML reserves (W3C XML 1.0, section 2.4), for attribute values
// and element text written by hand (condense's mesh export, postproc's XDMF).
#include <string>

namespace nvh {

inline std::string xml_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace nvh
