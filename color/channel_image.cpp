// ChannelImage's one method, outside the image module (image_module.h) that fills it: the accuracy
// sweep looks channels up in what the module read.
#include <algorithm>

#include "color/image_input.h"

namespace kiln {

int ChannelImage::channel(const std::string& name) const {
    auto it = std::find(channelNames.begin(), channelNames.end(), name);
    return it == channelNames.end() ? -1 : int(it - channelNames.begin());
}

}  // namespace kiln
