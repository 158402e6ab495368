// BRepThickness: the default colour map of the Thickness arrays in ParaView.
//
// When the plugin is loaded this registers the colour-map preset "BRepThickness" (the paper's
// map: white at the low end, then blue, green, yellow, red at the high end, in RGB space, with
// magenta for NaN, i.e. the failed samples) and the setting ".standard_presets.Thickness", by
// which ParaView applies that preset to every new colour map of an array named "Thickness" (the
// filter's ports 0 and 1). The preset then also appears in ParaView's preset list. The setting's
// priority is below the user's own settings, so a choice the user saves wins.
#include "vtkSMSettings.h"
#include "vtkSMTransferFunctionPresets.h"

namespace
{
const char* const PresetName = "BRepThickness";
const char* const Preset = R"json({
  "Name": "BRepThickness",
  "ColorSpace": "RGB",
  "RGBPoints": [0.0, 1.0, 1.0, 1.0,
                0.25, 0.0, 0.0, 1.0,
                0.5, 0.0, 1.0, 0.0,
                0.75, 1.0, 1.0, 0.0,
                1.0, 1.0, 0.0, 0.0],
  "NanColor": [1.0, 0.0, 1.0]
})json";

struct RegisterThicknessColorMap
{
  RegisterThicknessColorMap()
  {
    vtkSMTransferFunctionPresets* presets = vtkSMTransferFunctionPresets::GetInstance();
    if (!presets->HasPreset(PresetName))
      presets->AddPreset(PresetName, Preset);
    vtkSMSettings::GetInstance()->AddCollectionFromString(
      R"json({ "standard_presets": { "Thickness": "BRepThickness" } })json", 0.1);
  }
};
const RegisterThicknessColorMap registerOnLoad;
} // namespace
