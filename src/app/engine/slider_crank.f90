!> Closed-form kinematics of the centred slider-crank of the reference engine (scene.md): crank
!> axis z through the origin, cylinder axis y, crank angle theta = 0 puts the pin at +y (TDC).
!> Piston pin height y(theta) = r cos(theta) + sqrt(l^2 - r^2 sin^2(theta)) and its first two
!> derivatives in theta; cylinder volume V(theta) and dV/dtheta (theory.md section 6). At constant
!> crank speed omega the piston velocity is omega dy/dtheta and its acceleration
!> omega^2 d2y/dtheta2. All functions require l > r > 0 (callers check it once).
module ffrf_app_engine_slider_crank
   use ffrf_core_kinds, only: dp, pi
   implicit none
   private
   public :: piston_position, piston_dy_dtheta, piston_d2y_dtheta2
   public :: cylinder_volume, cylinder_dvolume, swept_volume, clearance_volume

contains

   !> Piston pin height above the crank axis, y(theta) = r cos(theta) + sqrt(l^2 - r^2 sin^2(theta))
   !> (m); y(0) = r + l at TDC, y(pi) = l - r at BDC.
   pure function piston_position(theta, crank_radius, conrod_length) result(y)
      !> Crank angle from TDC (rad)
      real(dp), intent(in) :: theta
      !> Crank radius r = stroke / 2 (m)
      real(dp), intent(in) :: crank_radius
      !> Conrod length l between the pin centres (m), l > r
      real(dp), intent(in) :: conrod_length
      real(dp) :: y
      y = crank_radius * cos(theta) + rod_root(theta, crank_radius, conrod_length)
   end function piston_position

   !> dy/dtheta = -r sin(theta) - r^2 sin(theta) cos(theta) / sqrt(l^2 - r^2 sin^2(theta)) (m/rad).
   pure function piston_dy_dtheta(theta, crank_radius, conrod_length) result(dy)
      !> Crank angle from TDC (rad)
      real(dp), intent(in) :: theta
      !> Crank radius r (m)
      real(dp), intent(in) :: crank_radius
      !> Conrod length l (m), l > r
      real(dp), intent(in) :: conrod_length
      real(dp) :: dy
      real(dp) :: s, c
      s = sin(theta)
      c = cos(theta)
      dy = -crank_radius * s &
         - crank_radius**2 * s * c / rod_root(theta, crank_radius, conrod_length)
   end function piston_dy_dtheta

   !> d2y/dtheta2 = -r cos(theta) - r^2 cos(2 theta) / w - r^4 sin^2(theta) cos^2(theta) / w^3,
   !> w = sqrt(l^2 - r^2 sin^2(theta)) (m/rad^2).
   pure function piston_d2y_dtheta2(theta, crank_radius, conrod_length) result(d2y)
      !> Crank angle from TDC (rad)
      real(dp), intent(in) :: theta
      !> Crank radius r (m)
      real(dp), intent(in) :: crank_radius
      !> Conrod length l (m), l > r
      real(dp), intent(in) :: conrod_length
      real(dp) :: d2y
      real(dp) :: s, c, w
      s = sin(theta)
      c = cos(theta)
      w = rod_root(theta, crank_radius, conrod_length)
      d2y = -crank_radius * c - crank_radius**2 * (c * c - s * s) / w &
         - crank_radius**4 * (s * c)**2 / w**3
   end function piston_d2y_dtheta2

   !> Cylinder volume V(theta) = V_c + (pi B^2 / 4) (l + r - y(theta)) (theory.md section 6), m^3.
   pure function cylinder_volume(theta, bore, crank_radius, conrod_length, v_clearance) result(v)
      !> Crank angle from TDC (rad)
      real(dp), intent(in) :: theta
      !> Bore B (m)
      real(dp), intent(in) :: bore
      !> Crank radius r (m)
      real(dp), intent(in) :: crank_radius
      !> Conrod length l (m), l > r
      real(dp), intent(in) :: conrod_length
      !> Clearance volume V_c = V(0) (m^3)
      real(dp), intent(in) :: v_clearance
      real(dp) :: v
      real(dp) :: s
      ! l + r - y written without the cancellation of y near TDC: l - w = r^2 s^2 / (l + w)
      s = sin(theta)
      v = v_clearance + 0.25_dp * pi * bore**2 * (crank_radius * (1.0_dp - cos(theta)) &
         + (crank_radius * s)**2 / (conrod_length + rod_root(theta, crank_radius, conrod_length)))
   end function cylinder_volume

   !> dV/dtheta = (pi B^2 / 4) r sin(theta) [1 + r cos(theta) / sqrt(l^2 - r^2 sin^2(theta))]
   !> (theory.md section 6), m^3/rad.
   pure function cylinder_dvolume(theta, bore, crank_radius, conrod_length) result(dv)
      !> Crank angle from TDC (rad)
      real(dp), intent(in) :: theta
      !> Bore B (m)
      real(dp), intent(in) :: bore
      !> Crank radius r (m)
      real(dp), intent(in) :: crank_radius
      !> Conrod length l (m), l > r
      real(dp), intent(in) :: conrod_length
      real(dp) :: dv
      dv = -0.25_dp * pi * bore**2 * piston_dy_dtheta(theta, crank_radius, conrod_length)
   end function cylinder_dvolume

   !> Displacement V_d = pi B^2 S / 4 (m^3).
   pure function swept_volume(bore, stroke) result(v)
      !> Bore B (m)
      real(dp), intent(in) :: bore
      !> Stroke S = 2 r (m)
      real(dp), intent(in) :: stroke
      real(dp) :: v
      v = 0.25_dp * pi * bore**2 * stroke
   end function swept_volume

   !> Clearance volume V_c = V_d / (r_c - 1) (m^3), r_c > 1.
   pure function clearance_volume(bore, stroke, compression_ratio) result(v)
      !> Bore B (m)
      real(dp), intent(in) :: bore
      !> Stroke S (m)
      real(dp), intent(in) :: stroke
      !> Compression ratio r_c = (V_c + V_d) / V_c
      real(dp), intent(in) :: compression_ratio
      real(dp) :: v
      v = swept_volume(bore, stroke) / (compression_ratio - 1.0_dp)
   end function clearance_volume

   !> sqrt(l^2 - r^2 sin^2(theta)), the conrod's projection on the cylinder axis (m).
   pure function rod_root(theta, crank_radius, conrod_length) result(w)
      !> Crank angle (rad)
      real(dp), intent(in) :: theta
      !> Crank radius r (m)
      real(dp), intent(in) :: crank_radius
      !> Conrod length l (m), l > r
      real(dp), intent(in) :: conrod_length
      real(dp) :: w
      w = sqrt(conrod_length**2 - (crank_radius * sin(theta))**2)
   end function rod_root

end module ffrf_app_engine_slider_crank
