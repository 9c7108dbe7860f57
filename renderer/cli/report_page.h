// A generated report page (kiln report): headings, paragraphs, rows of captioned images and tables,
// held as blocks and written as HTML (every text escaped, no remote assets) or as Markdown for a
// course page repository; written to a temporary name and renamed.
#pragma once

#include <string>
#include <vector>

namespace kiln {

enum class PageFormat { Html, Markdown };

class ReportPage {
  public:
    explicit ReportPage(std::string title) : title_(std::move(title)) {}

    struct Image {
        std::string src;      // relative to the page
        std::string caption;  // what it shows
        std::string detail;   // how it was made (shown as code)
    };
    void heading(int level, const std::string& text);
    void paragraph(const std::string& text);
    void code(const std::string& text);  // a preformatted block
    void images(const std::vector<Image>& row);
    void table(const std::vector<std::string>& header,
               const std::vector<std::vector<std::string>>& rows);

    std::string html() const;
    std::string markdown() const;
    // Throws std::runtime_error naming the path when it cannot be written.
    void write(const std::string& path, PageFormat format) const;

    static std::string escape(const std::string& text);          // HTML
    static std::string escapeMarkdown(const std::string& text);  // inline Markdown

  private:
    enum class Kind { Heading, Paragraph, Code, Images, Table };
    struct Block {
        Kind kind;
        int level = 0;
        std::vector<std::string> texts;  // heading/paragraph/code: one; table: the header
        std::vector<Image> images;
        std::vector<std::vector<std::string>> rows;
    };
    std::string title_;
    std::vector<Block> blocks_;
};

}  // namespace kiln
