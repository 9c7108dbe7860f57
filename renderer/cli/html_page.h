// A small HTML page writer for generated reports: headings, paragraphs, rows of captioned images
// and tables, every text escaped; written to a temporary name and renamed.
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace kiln {

class HtmlPage {
  public:
    explicit HtmlPage(std::string title) : title_(std::move(title)) {}

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
    // Throws std::runtime_error naming the path when it cannot be written.
    void write(const std::string& path) const;

    static std::string escape(const std::string& text);

  private:
    std::string title_;
    std::ostringstream body_;
};

}  // namespace kiln
