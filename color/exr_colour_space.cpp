#include "color/exr_colour_space.h"

#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <stdexcept>

namespace kiln {

void stampExrColourSpace(const std::string& from, const std::string& to,
                         const std::string& colourSpace) {
    try {
        Imf::InputFile in(from.c_str());
        Imf::Header header = in.header();
        header.insert("oiio:ColorSpace", Imf::StringAttribute(colourSpace));
        Imf::OutputFile out(to.c_str(), header);
        out.copyPixels(in);
    } catch (const std::exception& e) {
        throw std::runtime_error(from +
                                 ": cannot add the colour space to the EXR header: " + e.what());
    }
}

}  // namespace kiln
