#include "renderer/cli/html_page.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "color/atomic_file.h"

namespace kiln {

std::string HtmlPage::escape(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
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
                out += "&#39;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

void HtmlPage::heading(int level, const std::string& text) {
    body_ << "<h" << level << ">" << escape(text) << "</h" << level << ">\n";
}

void HtmlPage::paragraph(const std::string& text) { body_ << "<p>" << escape(text) << "</p>\n"; }

void HtmlPage::code(const std::string& text) { body_ << "<pre>" << escape(text) << "</pre>\n"; }

void HtmlPage::images(const std::vector<Image>& row) {
    body_ << "<div class=\"row\">\n";
    for (const Image& im : row)
        body_ << "<figure><img src=\"" << escape(im.src) << "\" alt=\"" << escape(im.caption)
              << "\"><figcaption>" << escape(im.caption) << "<br><code>" << escape(im.detail)
              << "</code></figcaption></figure>\n";
    body_ << "</div>\n";
}

void HtmlPage::table(const std::vector<std::string>& header,
                     const std::vector<std::vector<std::string>>& rows) {
    body_ << "<table>\n<tr>";
    for (const std::string& h : header) body_ << "<th>" << escape(h) << "</th>";
    body_ << "</tr>\n";
    for (const auto& row : rows) {
        body_ << "<tr>";
        for (const std::string& cell : row) body_ << "<td>" << escape(cell) << "</td>";
        body_ << "</tr>\n";
    }
    body_ << "</table>\n";
}

std::string HtmlPage::html() const {
    return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
           escape(title_) +
           "</title>\n<style>\n"
           "body{font-family:sans-serif;margin:2em;max-width:1400px;color:#222}\n"
           ".row{display:flex;flex-wrap:wrap;gap:12px;margin:8px 0}\n"
           "figure{margin:0;width:300px}figure img{width:100%;image-rendering:pixelated;"
           "border:1px solid #ccc}\n"
           "figcaption{font-size:12px}code,pre{font-size:11px;color:#555}\n"
           "table{border-collapse:collapse;margin:8px 0}td,th{border:1px solid #bbb;"
           "padding:3px 8px;font-size:13px;text-align:right}\n"
           "</style>\n</head>\n<body>\n<h1>" +
           escape(title_) + "</h1>\n" + body_.str() + "</body>\n</html>\n";
}

void HtmlPage::write(const std::string& path) const { writeFileAtomically(path, html()); }

}  // namespace kiln
