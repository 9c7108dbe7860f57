// An ACES-style OCIO config for tests: scene_linear is ACEScg, every transform an OCIO built-in,
// so the test needs no files but this text (test_aces_config.cpp, test_install.cpp).
#pragma once

namespace kiln::test {

inline constexpr const char* kAcesConfig = R"(ocio_profile_version: 2
roles:
  default: acescg
  scene_linear: acescg
  aces_interchange: aces
  texture_paint: srgb_texture
displays:
  sRGB:
    - !<View> {name: Standard, colorspace: srgb_display}
active_displays: []
active_views: []
looks:
  - !<Look> {name: Brighter, process_space: acescg, transform: !<ExponentTransform> {value: [0.8, 0.8, 0.8, 1]}}
colorspaces:
  - !<ColorSpace> {name: lin_rec709, isdata: false}
  - !<ColorSpace>
    name: acescg
    from_reference: !<BuiltinTransform> {style: "UTILITY - ACES-AP1_to_LINEAR-REC709_BFD", direction: inverse}
  - !<ColorSpace>
    name: aces
    from_reference: !<GroupTransform>
      children:
        - !<BuiltinTransform> {style: "UTILITY - ACES-AP1_to_LINEAR-REC709_BFD", direction: inverse}
        - !<BuiltinTransform> {style: ACEScg_to_ACES2065-1}
  - !<ColorSpace>
    name: srgb_texture
    from_reference: !<ExponentWithLinearTransform> {gamma: 2.4, offset: 0.055, direction: inverse}
  - !<ColorSpace>
    name: srgb_display
    from_reference: !<ExponentWithLinearTransform> {gamma: 2.4, offset: 0.055, direction: inverse}
)";

}  // namespace kiln::test
