// BRepThickness: the default colour maps and scalar-bar titles of the filter's arrays in ParaView.
//
// When the plugin is loaded this registers the colour-map preset "BRepThickness" (the paper's
// map: white at the low end, then blue, green, yellow, red at the high end, in RGB space, with
// magenta for NaN, i.e. the failed samples) and the setting ".standard_presets.Thickness", by
// which ParaView applies that preset to every new colour map of an array named "Thickness" (the
// filter's ports 0 and 1). The preset then also appears in ParaView's preset list. The setting's
// priority is below the user's own settings, so a choice the user saves wins.
//
// The same settings give the scalar bars their titles with the unit (".array_lookup_tables.
// <array>.Title", which ParaView 5.11 reads when it first shows a scalar bar; it ignores the
// component name of a one-component array) and make ThicknessClass a categorical map: one
// colour and one label per class (brt::SampleClass), thin walls red, thick spots blue. The
// reader converts every file to millimetres (docs/DataContract.md), so the unit is fixed.
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

const char* const Settings = R"json({
  "standard_presets": { "Thickness": "BRepThickness", "RayThickness": "BRepThickness",
    "Gap": "BRepThickness",
    "ThicknessClass": "BRepThickness classes" },
  "array_lookup_tables": {
    "Thickness": { "Title": "Thickness (mm)" },
    "RayThickness": { "Title": "Ray thickness (mm)" },
    "Gap": { "Title": "Gap (mm)" },
    "Radius": { "Title": "Radius (mm)" },
    "ContactAngle": { "Title": "Contact angle (deg)" },
    "ThicknessClass": { "Title": "Thickness class" }
  }
})json";

// Categorical: brt::SampleClass 0 failed (magenta, the NaN colour of Thickness), 1 thin (red),
// 2 ok (light grey), 3 thick (blue), 4 edge zone (amber).
const char* const ClassesName = "BRepThickness classes";
const char* const Classes = R"json({
  "Name": "BRepThickness classes",
  "Annotations": ["0", "failed", "1", "thin", "2", "ok", "3", "thick", "4", "edge zone"],
  "IndexedColors": [1.0, 0.0, 1.0,
                    0.85, 0.1, 0.1,
                    0.82, 0.82, 0.82,
                    0.15, 0.35, 0.9,
                    0.98, 0.8, 0.35]
})json";

struct RegisterThicknessColorMap
{
  RegisterThicknessColorMap()
  {
    vtkSMTransferFunctionPresets* presets = vtkSMTransferFunctionPresets::GetInstance();
    if (!presets->HasPreset(PresetName))
      presets->AddPreset(PresetName, Preset);
    if (!presets->HasPreset(ClassesName))
      presets->AddPreset(ClassesName, Classes);
    vtkSMSettings::GetInstance()->AddCollectionFromString(Settings, 0.1);
  }
};
const RegisterThicknessColorMap registerOnLoad;
} // namespace
