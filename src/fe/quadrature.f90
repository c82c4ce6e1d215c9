!> Quadrature rules on the reference tetrahedron {x, y, z >= 0, x + y + z <= 1} (volume 1/6) and
!> the reference triangle {x, y >= 0, x + y <= 1} (area 1/2). All weights are positive and sum to
!> the reference measure. Degree d means every polynomial of total degree <= d is integrated
!> exactly; the unit tests check all monomials x^a y^b z^c against a! b! c! / (a + b + c + 3)!
!> (tetrahedron) and a! b! / (a + b + 2)! (triangle).
!>
!> | rule  | points | degree | source                                                        |
!> |-------|--------|--------|---------------------------------------------------------------|
!> | TET1  | 1      | 1      | centroid                                                      |
!> | TET4  | 4      | 2      | a = (5 - sqrt 5)/20 (Keast 1986)                              |
!> | TET14 | 14     | 5      | Walkington (2000): two s31 orbits and one s22 orbit, w > 0    |
!> | TRI3  | 3      | 2      | (1/6, 1/6) orbit (Strang & Fix 1973)                          |
!> | TRI7  | 7      | 5      | Radon (1948), closed form with sqrt(15)                       |
!>
!> The TET14 orbit parameters were recomputed for ffrf to 25 digits by solving the moment
!> equations of all 56 monomials of degree <= 5 with Newton's method in 40-digit arithmetic
!> (residual 3e-42), starting from the rounded literature values.
module ffrf_fe_quadrature
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   implicit none
   private
   public :: quadrature_t, tet_quadrature, tri_quadrature
   public :: TET1_POINTS, TET1_WEIGHTS, TET4_POINTS, TET4_WEIGHTS, TET14_POINTS, TET14_WEIGHTS
   public :: TRI3_POINTS, TRI3_WEIGHTS, TRI7_POINTS, TRI7_WEIGHTS

   !> A quadrature rule on a reference simplex.
   type :: quadrature_t
      !> Highest total degree integrated exactly
      integer :: degree = 0
      !> Number of points
      integer :: num_points = 0
      !> Reference coordinates (dim, num_points), dim = 3 (tetrahedron) or 2 (triangle)
      real(dp), allocatable :: points(:, :)
      !> Weights, positive, summing to 1/6 (tetrahedron) or 1/2 (triangle)
      real(dp), allocatable :: weights(:)
   end type quadrature_t

   ! ---- tetrahedron, 1 point, degree 1
   real(dp), parameter :: TET1_POINTS(3, 1) = reshape([0.25_dp, 0.25_dp, 0.25_dp], [3, 1])
   real(dp), parameter :: TET1_WEIGHTS(1) = [1.0_dp/6.0_dp]

   ! ---- tetrahedron, 4 points, degree 2: barycentric (b, a, a, a) and permutations
   real(dp), parameter :: T4A = (5.0_dp - sqrt(5.0_dp))/20.0_dp
   real(dp), parameter :: T4B = (5.0_dp + 3.0_dp*sqrt(5.0_dp))/20.0_dp
   real(dp), parameter :: TET4_POINTS(3, 4) = reshape([ &
      T4A, T4A, T4A, T4B, T4A, T4A, T4A, T4B, T4A, T4A, T4A, T4B], [3, 4])
   real(dp), parameter :: TET4_WEIGHTS(4) = 1.0_dp/24.0_dp

   ! ---- tetrahedron, 14 points, degree 5 (Walkington 2000), weights for volume 1/6
   real(dp), parameter :: T14A1 = 0.3108859192633006097973457_dp
   real(dp), parameter :: T14W1 = 0.01878132095300264179986428_dp
   real(dp), parameter :: T14A2 = 0.09273525031089122640232391_dp
   real(dp), parameter :: T14W2 = 0.01224884051939365825728503_dp
   real(dp), parameter :: T14C = 0.04550370412564964949188053_dp
   real(dp), parameter :: T14W3 = 0.007091003462846911073011571_dp
   real(dp), parameter :: T14B1 = 1.0_dp - 3.0_dp*T14A1
   real(dp), parameter :: T14B2 = 1.0_dp - 3.0_dp*T14A2
   real(dp), parameter :: T14D = 0.5_dp - T14C
   real(dp), parameter :: TET14_POINTS(3, 14) = reshape([ &
      T14A1, T14A1, T14A1, T14B1, T14A1, T14A1, T14A1, T14B1, T14A1, T14A1, T14A1, T14B1, &
      T14A2, T14A2, T14A2, T14B2, T14A2, T14A2, T14A2, T14B2, T14A2, T14A2, T14A2, T14B2, &
      T14D, T14C, T14C, T14C, T14D, T14C, T14C, T14C, T14D, &
      T14D, T14D, T14C, T14D, T14C, T14D, T14C, T14D, T14D], [3, 14])
   real(dp), parameter :: TET14_WEIGHTS(14) = [T14W1, T14W1, T14W1, T14W1, &
      T14W2, T14W2, T14W2, T14W2, T14W3, T14W3, T14W3, T14W3, T14W3, T14W3]

   ! ---- triangle, 3 points, degree 2
   real(dp), parameter :: TRI3_POINTS(2, 3) = reshape([1.0_dp/6.0_dp, 1.0_dp/6.0_dp, &
      2.0_dp/3.0_dp, 1.0_dp/6.0_dp, 1.0_dp/6.0_dp, 2.0_dp/3.0_dp], [2, 3])
   real(dp), parameter :: TRI3_WEIGHTS(3) = 1.0_dp/6.0_dp

   ! ---- triangle, 7 points, degree 5 (Radon 1948), weights for area 1/2
   real(dp), parameter :: S15 = sqrt(15.0_dp)
   real(dp), parameter :: R7A = (6.0_dp - S15)/21.0_dp
   real(dp), parameter :: R7B = (6.0_dp + S15)/21.0_dp
   real(dp), parameter :: R7WA = (155.0_dp - S15)/2400.0_dp
   real(dp), parameter :: R7WB = (155.0_dp + S15)/2400.0_dp
   real(dp), parameter :: TRI7_POINTS(2, 7) = reshape([1.0_dp/3.0_dp, 1.0_dp/3.0_dp, &
      R7A, R7A, 1.0_dp - 2.0_dp*R7A, R7A, R7A, 1.0_dp - 2.0_dp*R7A, &
      R7B, R7B, 1.0_dp - 2.0_dp*R7B, R7B, R7B, 1.0_dp - 2.0_dp*R7B], [2, 7])
   real(dp), parameter :: TRI7_WEIGHTS(7) = [9.0_dp/80.0_dp, R7WA, R7WA, R7WA, R7WB, R7WB, R7WB]

contains

   !> The smallest built-in tetrahedron rule exact to total degree `degree` (0..5).
   subroutine tet_quadrature(degree, rule, error)
      !> Required degree of exactness, 0..5
      integer, intent(in) :: degree
      !> The rule
      type(quadrature_t), intent(out) :: rule
      !> Degree outside 0..5
      type(error_t), allocatable, intent(out) :: error
      select case (degree)
      case (0:1)
         call set_rule(rule, 1, TET1_POINTS, TET1_WEIGHTS)
      case (2)
         call set_rule(rule, 2, TET4_POINTS, TET4_WEIGHTS)
      case (3:5)
         call set_rule(rule, 5, TET14_POINTS, TET14_WEIGHTS)
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, 'tetrahedron quadrature of degree ' // &
            to_str(degree) // ' is not available; degrees 0 to 5 are')
      end select
   end subroutine tet_quadrature

   !> The smallest built-in triangle rule exact to total degree `degree` (0..5).
   subroutine tri_quadrature(degree, rule, error)
      !> Required degree of exactness, 0..5
      integer, intent(in) :: degree
      !> The rule
      type(quadrature_t), intent(out) :: rule
      !> Degree outside 0..5
      type(error_t), allocatable, intent(out) :: error
      select case (degree)
      case (0:2)
         call set_rule(rule, 2, TRI3_POINTS, TRI3_WEIGHTS)
      case (3:5)
         call set_rule(rule, 5, TRI7_POINTS, TRI7_WEIGHTS)
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, 'triangle quadrature of degree ' // &
            to_str(degree) // ' is not available; degrees 0 to 5 are')
      end select
   end subroutine tri_quadrature

   subroutine set_rule(rule, degree, points, weights)
      type(quadrature_t), intent(inout) :: rule
      integer, intent(in) :: degree
      real(dp), intent(in) :: points(:, :), weights(:)
      rule%degree = degree
      rule%num_points = size(weights)
      rule%points = points
      rule%weights = weights
   end subroutine set_rule

end module ffrf_fe_quadrature
