// The package's drape messages under names that do not clash with the core.
//
// The message package and the core share the namespace `virtual_tryon`, and four messages have
// the names of core types: virtual_tryon/Panel, Seam, GarmentPattern and DrapeReport would each
// generate `typedef ... virtual_tryon::Panel` (etc.) next to the core's `struct
// virtual_tryon::Panel`, which does not compile. This header includes the generated headers with
// those four typedefs renamed to PanelMsg, SeamMsg, GarmentPatternMsg and DrapeReportMsg (the
// message templates Panel_<A>, ... and the wire names "virtual_tryon/Panel", ... are unchanged).
//
// ALWAYS include this header instead of <virtual_tryon/Panel.h>, <virtual_tryon/Seam.h>,
// <virtual_tryon/GarmentPattern.h>, <virtual_tryon/DrapeReport.h> or <virtual_tryon/Drape.h>:
// a translation unit that includes one of those directly cannot include a core pattern or drape
// header, and (because of the include guards) a direct include before this one defeats the
// renaming.
#pragma once

// Everything the generated headers include, first, so that the renaming macros below touch
// nothing but the generated code.
#include <geometry_msgs/Pose.h>
#include <pcl_msgs/PolygonMesh.h>
#include <ros/builtin_message_traits.h>
#include <ros/message_operations.h>
#include <ros/serialization.h>
#include <ros/service_traits.h>
#include <ros/types.h>
#include <std_msgs/Header.h>
#include <virtual_tryon/PenetrationReport.h>

#include <memory>
#include <string>
#include <vector>

#if defined(VIRTUAL_TRYON_MESSAGE_PANEL_H) || defined(VIRTUAL_TRYON_MESSAGE_SEAM_H) ||            \
    defined(VIRTUAL_TRYON_MESSAGE_GARMENTPATTERN_H) || defined(VIRTUAL_TRYON_MESSAGE_DRAPEREPORT_H)
#error "a virtual_tryon drape message header was included directly; include virtual_tryon/ros/msgs.h first"
#endif

#pragma push_macro("Panel")
#pragma push_macro("Seam")
#pragma push_macro("GarmentPattern")
#pragma push_macro("DrapeReport")
#define Panel PanelMsg
#define Seam SeamMsg
#define GarmentPattern GarmentPatternMsg
#define DrapeReport DrapeReportMsg
#include <virtual_tryon/Drape.h>
#include <virtual_tryon/DrapeReport.h>
#include <virtual_tryon/GarmentPattern.h>
#include <virtual_tryon/Panel.h>
#include <virtual_tryon/Seam.h>
#undef Panel
#undef Seam
#undef GarmentPattern
#undef DrapeReport
#pragma pop_macro("Panel")
#pragma pop_macro("Seam")
#pragma pop_macro("GarmentPattern")
#pragma pop_macro("DrapeReport")
