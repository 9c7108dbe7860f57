#include "renderer/cli/report_page.h"

#include <sstream>

#include "color/atomic_file.h"

namespace kiln {

std::string ReportPage::escape(const std::string& text) {
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

std::string ReportPage::escapeMarkdown(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
        if (std::string("\\`*_[]<>|#").find(c) != std::string::npos) out += '\\';
        out += c;
    }
    return out;
}

void ReportPage::heading(int level, const std::string& text) {
    blocks_.push_back({Kind::Heading, level, {text}, {}, {}});
}

void ReportPage::paragraph(const std::string& text) {
    blocks_.push_back({Kind::Paragraph, 0, {text}, {}, {}});
}

void ReportPage::code(const std::string& text) {
    blocks_.push_back({Kind::Code, 0, {text}, {}, {}});
}

void ReportPage::images(const std::vector<Image>& row) {
    blocks_.push_back({Kind::Images, 0, {}, row, {}});
}

void ReportPage::table(const std::vector<std::string>& header,
                       const std::vector<std::vector<std::string>>& rows) {
    blocks_.push_back({Kind::Table, 0, header, {}, rows});
}

namespace {

void htmlBlock(std::ostringstream& o, const std::string& tag, const std::string& text) {
    o << "<" << tag << ">" << ReportPage::escape(text) << "</" << tag << ">\n";
}

}  // namespace

std::string ReportPage::html() const {
    std::ostringstream o;
    o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>"
      << escape(title_)
      << "</title>\n<style>\n"
         "body{font-family:sans-serif;margin:2em;max-width:1500px;color:#222;line-height:1.45}\n"
         "p{max-width:60em}\n"
         ".row{display:flex;flex-wrap:wrap;gap:12px;margin:8px 0}\n"
         "figure{margin:0;width:360px}figure img{width:100%;border:1px solid #ccc}\n"
         "figcaption{font-size:12px}code,pre{font-size:11px;color:#555;word-break:break-all}\n"
         "table{border-collapse:collapse;margin:8px 0}td,th{border:1px solid #bbb;"
         "padding:3px 8px;font-size:13px;text-align:right}\n"
         "</style>\n</head>\n<body>\n<h1>"
      << escape(title_) << "</h1>\n";
    for (const Block& b : blocks_) {
        switch (b.kind) {
            case Kind::Heading:
                htmlBlock(o, std::string(1, 'h').append(std::to_string(b.level)), b.texts[0]);
                break;
            case Kind::Paragraph:
                htmlBlock(o, "p", b.texts[0]);
                break;
            case Kind::Code:
                htmlBlock(o, "pre", b.texts[0]);
                break;
            case Kind::Images:
                o << "<div class=\"row\">\n";
                for (const Image& im : b.images)
                    o << "<figure><img src=\"" << escape(im.src) << "\" alt=\""
                      << escape(im.caption) << "\"><figcaption>" << escape(im.caption)
                      << "<br><code>" << escape(im.detail) << "</code></figcaption></figure>\n";
                o << "</div>\n";
                break;
            case Kind::Table:
                o << "<table>\n<tr>";
                for (const std::string& h : b.texts) o << "<th>" << escape(h) << "</th>";
                o << "</tr>\n";
                for (const auto& row : b.rows) {
                    o << "<tr>";
                    for (const std::string& cell : row) o << "<td>" << escape(cell) << "</td>";
                    o << "</tr>\n";
                }
                o << "</table>\n";
                break;
        }
    }
    o << "</body>\n</html>\n";
    return o.str();
}

namespace {

// A table row of Markdown: cells escaped, so a '|' in a command cannot split a cell.
std::string markdownRow(const std::vector<std::string>& cells) {
    std::string out = "|";
    for (const std::string& c : cells)
        out.append(" ").append(ReportPage::escapeMarkdown(c)).append(" |");
    return out + "\n";
}

}  // namespace

std::string ReportPage::markdown() const {
    std::ostringstream o;
    o << "# " << escapeMarkdown(title_) << "\n\n";
    for (const Block& b : blocks_) {
        switch (b.kind) {
            case Kind::Heading:
                o << std::string(size_t(b.level), '#') << " " << escapeMarkdown(b.texts[0])
                  << "\n\n";
                break;
            case Kind::Paragraph:
                o << escapeMarkdown(b.texts[0]) << "\n\n";
                break;
            case Kind::Code:
                o << "```\n" << b.texts[0] << "\n```\n\n";
                break;
            case Kind::Images:
                for (const Image& im : b.images)
                    o << "![" << escapeMarkdown(im.caption) << "](" << im.src << ")  \n"
                      << escapeMarkdown(im.caption) << ": `" << im.detail << "`\n\n";
                break;
            case Kind::Table:
                o << markdownRow(b.texts) << "|" <<
                    [&] {
                        std::string rule;
                        for (size_t i = 0; i < b.texts.size(); ++i) rule += "---|";
                        return rule;
                    }()
                  << "\n";
                for (const auto& row : b.rows) o << markdownRow(row);
                o << "\n";
                break;
        }
    }
    return o.str();
}

void ReportPage::write(const std::string& path, PageFormat format) const {
    writeFileAtomically(path, format == PageFormat::Html ? html() : markdown());
}

}  // namespace kiln
