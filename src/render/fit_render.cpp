#include "virtual_tryon/render/fit_render.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkOutputWindow.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>

namespace virtual_tryon {
namespace {

vtkSmartPointer<vtkPolyData> toPolyData(const TriMesh& m) {
  vtkNew<vtkPoints> points;
  points->SetNumberOfPoints(m.V.rows());
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) points->SetPoint(i, m.V(i, 0), m.V(i, 1), m.V(i, 2));
  vtkNew<vtkCellArray> cells;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const vtkIdType ids[3] = {m.F(f, 0), m.F(f, 1), m.F(f, 2)};
    cells->InsertNextCell(3, ids);
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(cells);
  return poly;
}

// Smooth shading from point normals (both sides of an open garment are lit).
vtkSmartPointer<vtkActor> meshActor(const vtkSmartPointer<vtkPolyData>& poly, vtkLookupTable* lut, double range) {
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputData(poly);
  normals->SplittingOff();
  normals->ConsistencyOn();
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(normals->GetOutputPort());
  if (lut) {
    mapper->SetLookupTable(lut);
    mapper->SetScalarRange(0.0, range);
    mapper->ScalarVisibilityOn();
    mapper->SetColorModeToMapScalars();
    mapper->InterpolateScalarsBeforeMappingOn();
  } else {
    mapper->ScalarVisibilityOff();
  }
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetInterpolationToPhong();
  actor->GetProperty()->SetSpecular(0.15);
  actor->GetProperty()->SetSpecularPower(20);
  return actor;
}

// Blue (no strain) through green and yellow to red (strain_scale and beyond).
vtkSmartPointer<vtkLookupTable> strainColours() {
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  lut->SetNumberOfTableValues(256);
  lut->SetHueRange(0.667, 0.0);
  lut->SetSaturationRange(0.85, 0.85);
  lut->SetValueRange(0.95, 0.95);
  lut->Build();
  return lut;
}

vtkSmartPointer<vtkScalarBarActor> strainBar(vtkLookupTable* lut, double scale) {
  auto bar = vtkSmartPointer<vtkScalarBarActor>::New();
  bar->SetLookupTable(lut);
  (void)scale;
  bar->SetTitle("strain");
  bar->SetNumberOfLabels(4);
  bar->SetLabelFormat("%.2f");
  bar->SetOrientationToHorizontal();
  bar->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  bar->GetPositionCoordinate()->SetValue(0.15, 0.01);
  bar->SetWidth(0.7);
  bar->SetHeight(0.08);
  bar->UnconstrainedFontSizeOn();
  bar->GetTitleTextProperty()->SetColor(0.1, 0.1, 0.1);
  bar->GetTitleTextProperty()->SetFontSize(16);
  bar->GetTitleTextProperty()->ShadowOff();
  bar->GetTitleTextProperty()->ItalicOff();
  bar->GetLabelTextProperty()->SetColor(0.1, 0.1, 0.1);
  bar->GetLabelTextProperty()->SetFontSize(14);
  bar->GetLabelTextProperty()->ShadowOff();
  bar->GetLabelTextProperty()->ItalicOff();
  return bar;
}

// The camera direction (from the scene's centre towards the eye) of a view; false if unknown.
bool viewDirection(const std::string& view, const FitRenderParams& p, Eigen::Vector3d& dir) {
  const Eigen::Vector3d front = p.front.normalized(), up = p.up.normalized();
  if (view == "front") dir = front;
  else if (view == "back") dir = -front;
  else if (view == "side") dir = up.cross(front).normalized();  // the body's left
  else return false;
  return true;
}

// One picture: the camera on `dir` at a distance that frames the bounding box [lo, hi].
bool renderView(vtkRenderer* renderer, vtkRenderWindow* window, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                const Eigen::Vector3d& dir, const FitRenderParams& p, const std::string& file) {
  const Eigen::Vector3d up = p.up.normalized();
  const double height = std::max((hi - lo).dot(up.cwiseAbs()), 1e-3);
  const Eigen::Vector3d c = 0.5 * (lo + hi) - 0.06 * height * up;  // room below for the colour bar
  const double radius = 0.5 * (hi - lo).norm();
  vtkCamera* cam = renderer->GetActiveCamera();
  cam->SetFocalPoint(c.x(), c.y(), c.z());
  const Eigen::Vector3d eye = c + (4.0 * radius + 1.0) * dir;
  cam->SetPosition(eye.x(), eye.y(), eye.z());
  cam->SetViewUp(p.up.x(), p.up.y(), p.up.z());
  cam->SetParallelProjection(true);
  cam->SetParallelScale(0.62 * height);  // half the view height, with room for the title and bar
  renderer->ResetCameraClippingRange();
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkNew<vtkPNGWriter> png;
  png->SetFileName(file.c_str());
  png->SetInputConnection(grab->GetOutputPort());
  png->Write();
  return png->GetErrorCode() == 0;
}

std::string checkInput(const TriMesh& garment, const std::vector<double>& strain, const FitRenderParams& p) {
  if (garment.V.rows() == 0 || garment.F.rows() == 0) return "the garment is empty";
  if (!strain.empty() && strain.size() != static_cast<std::size_t>(garment.V.rows()))
    return "vertex_strain has " + std::to_string(strain.size()) + " values for " +
           std::to_string(garment.V.rows()) + " garment vertices";
  if (p.width < 16 || p.height < 16 || p.width > 8192 || p.height > 8192)
    return "width and height must be in [16, 8192] pixels";
  if (!(p.strain_scale > 0)) return "strain_scale must be > 0";
  if (p.up.norm() == 0 || p.front.norm() == 0 || p.up.normalized().cross(p.front.normalized()).norm() < 0.5)
    return "up and front must be non-zero and roughly perpendicular";
  Eigen::Vector3d dir;
  for (const std::string& v : p.views)
    if (!viewDirection(v, p, dir)) return "unknown view '" + v + "' (front, side, back)";
  if (!std::getenv("DISPLAY")) return "no X display (DISPLAY is unset): run under xvfb-run -a";
  return "";
}

}  // namespace

FitRenderResult renderFit(const TriMesh& body, const TriMesh& garment, const std::vector<double>& vertex_strain,
                          const std::string& out_prefix, const FitRenderParams& params) {
  const auto t0 = std::chrono::steady_clock::now();
  FitRenderResult r;
  r.message = checkInput(garment, vertex_strain, params);
  if (!r.message.empty()) return r;
  try {
    vtkOutputWindow::GetInstance()->SetDisplayModeToNever();  // VTK's own warnings stay quiet
    vtkNew<vtkRenderer> renderer;
    renderer->SetBackground(1.0, 1.0, 1.0);
    vtkNew<vtkRenderWindow> window;
    window->SetOffScreenRendering(1);
    window->SetMultiSamples(4);
    window->AddRenderer(renderer);
    window->SetSize(params.width, params.height);

    // Framed on the garment, grown by a quarter of its size each way (the body round it for
    // context), within the body's own box.
    const Eigen::Vector3d glo = garment.V.colwise().minCoeff().transpose();
    const Eigen::Vector3d ghi = garment.V.colwise().maxCoeff().transpose();
    const double grow = 0.25 * (ghi - glo).maxCoeff();
    Eigen::Vector3d lo = glo.array() - grow, hi = ghi.array() + grow;
    if (body.V.rows() > 0 && body.F.rows() > 0) {
      auto b = meshActor(toPolyData(body), nullptr, 0);
      b->GetProperty()->SetColor(0.78, 0.76, 0.74);
      renderer->AddActor(b);
      lo = lo.cwiseMax(body.V.colwise().minCoeff().transpose()).cwiseMin(glo);
      hi = hi.cwiseMin(body.V.colwise().maxCoeff().transpose()).cwiseMax(ghi);
    }
    auto poly = toPolyData(garment);
    vtkSmartPointer<vtkLookupTable> lut;
    double shown = 0;
    if (!vertex_strain.empty()) {
      vtkNew<vtkDoubleArray> s;
      s->SetName("strain");
      s->SetNumberOfValues(static_cast<vtkIdType>(vertex_strain.size()));
      for (std::size_t i = 0; i < vertex_strain.size(); ++i) {
        s->SetValue(static_cast<vtkIdType>(i), std::min(vertex_strain[i], params.strain_scale));
        shown = std::max(shown, vertex_strain[i]);
      }
      poly->GetPointData()->SetScalars(s);
      lut = strainColours();
      renderer->AddActor2D(strainBar(lut, params.strain_scale));
    }
    auto g = meshActor(poly, lut, params.strain_scale);
    if (!lut) g->GetProperty()->SetColor(0.25, 0.45, 0.8);
    renderer->AddActor(g);

    vtkNew<vtkTextActor> text;
    text->GetTextProperty()->SetColor(0.1, 0.1, 0.1);
    text->GetTextProperty()->SetFontSize(16);
    text->GetTextProperty()->SetVerticalJustificationToTop();
    text->SetPosition(10, params.height - 10);
    renderer->AddActor2D(text);
    for (const std::string& view : params.views) {
      Eigen::Vector3d dir;
      viewDirection(view, params, dir);
      std::string caption = params.title.empty() ? view : params.title + ": " + view;
      if (!vertex_strain.empty()) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "\nstrain |l/l0 - 1|: largest %.3f, red from %.2f", shown,
                      params.strain_scale);
        caption += buf;
      }
      text->SetInput(caption.c_str());
      const std::string file = out_prefix + "_" + view + ".png";
      if (!renderView(renderer, window, lo, hi, dir, params, file)) {
        r.message = "could not write " + file;
        return r;
      }
      r.files.push_back(file);
    }
    r.success = true;
  } catch (const std::exception& e) {
    r.message = std::string("rendering failed: ") + e.what();
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace virtual_tryon
