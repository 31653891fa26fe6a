!----------------------------------------------------------------------
! Unbalance-forced Jeffcott rotor on anisotropic supports with cubic
! (isotropic, hardening) bearing stiffness, in the fixed frame:
!
!   x'' + c x' + kx x + BETA x (x**2 + y**2) = e Om**2 cos(Om t),
!   y'' + c y' + ky y + BETA y (x**2 + y**2) = e Om**2 sin(Om t).
!
! The synchronous orbit is elliptic (kx /= ky): a periodic motion, not a rest
! point of any rotating frame. AUTO continues it as a periodic orbit (IPS = 2)
! of the autonomous extension by the standard forcing oscillator
!
!   u' = u + Om v - u (u**2 + v**2),   v' = -Om u + v - v (u**2 + v**2),
!
! whose attracting cycle is u = sin(Om t), v = cos(Om t) (period 2 pi / Om:
! AUTO's PAR(11) follows it); the forcing is e Om**2 (v, u). The extension adds
! two Floquet multipliers: 1 (the phase along the cycle) and exp(-2 T) = exp(-4 pi / Om)
! (the oscillator's radial direction).
!
! U = (x, y, x', y', u, v); PAR(1) = Om, PAR(2) = kx, PAR(3) = ky,
! PAR(4) = c, PAR(5) = BETA, PAR(6) = e. Jacobians by hand (JAC = 1).
!----------------------------------------------------------------------
SUBROUTINE FUNC(NDIM,U,ICP,PAR,IJAC,F,DFDU,DFDP)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM, ICP(*), IJAC
  DOUBLE PRECISION, INTENT(IN) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(OUT) :: F(NDIM)
  DOUBLE PRECISION, INTENT(INOUT) :: DFDU(NDIM,NDIM), DFDP(NDIM,*)
  DOUBLE PRECISION X, Y, XD, YD, US, VS, OM, KX, KY, C, BETA, E, R2, S2

  X = U(1)
  Y = U(2)
  XD = U(3)
  YD = U(4)
  US = U(5)
  VS = U(6)
  OM = PAR(1)
  KX = PAR(2)
  KY = PAR(3)
  C = PAR(4)
  BETA = PAR(5)
  E = PAR(6)
  R2 = X*X + Y*Y
  S2 = US*US + VS*VS
  F(1) = XD
  F(2) = YD
  F(3) = E*OM*OM*VS - C*XD - KX*X - BETA*X*R2
  F(4) = E*OM*OM*US - C*YD - KY*Y - BETA*Y*R2
  F(5) = US + OM*VS - US*S2
  F(6) = -OM*US + VS - VS*S2
  IF (IJAC == 0) RETURN

  DFDU(:,:) = 0.0D0
  DFDU(1,3) = 1.0D0
  DFDU(2,4) = 1.0D0
  DFDU(3,1) = -KX - BETA*(R2 + 2*X*X)
  DFDU(3,2) = -2*BETA*X*Y
  DFDU(3,3) = -C
  DFDU(3,6) = E*OM*OM
  DFDU(4,1) = -2*BETA*X*Y
  DFDU(4,2) = -KY - BETA*(R2 + 2*Y*Y)
  DFDU(4,4) = -C
  DFDU(4,5) = E*OM*OM
  DFDU(5,5) = 1.0D0 - S2 - 2*US*US
  DFDU(5,6) = OM - 2*US*VS
  DFDU(6,5) = -OM - 2*US*VS
  DFDU(6,6) = 1.0D0 - S2 - 2*VS*VS
  IF (IJAC == 1) RETURN

  DFDP(1:NDIM,1:6) = 0.0D0
  DFDP(3,1) = 2*E*OM*VS
  DFDP(4,1) = 2*E*OM*US
  DFDP(5,1) = VS
  DFDP(6,1) = -US
  DFDP(3,2) = -X
  DFDP(4,3) = -Y
  DFDP(3,4) = -XD
  DFDP(4,4) = -YD
  DFDP(3,5) = -X*R2
  DFDP(4,5) = -Y*R2
  DFDP(3,6) = OM*OM*VS
  DFDP(4,6) = OM*OM*US
END SUBROUTINE FUNC

SUBROUTINE STPNT(NDIM,U,PAR,T)
  ! Not used: the start is an orbit read from data (AUTO's `dat` constant).
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM
  DOUBLE PRECISION, INTENT(INOUT) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(IN) :: T
END SUBROUTINE STPNT

SUBROUTINE BCND
END SUBROUTINE BCND

SUBROUTINE ICND
END SUBROUTINE ICND

SUBROUTINE FOPT
END SUBROUTINE FOPT

SUBROUTINE PVLS(NDIM,U,PAR)
  ! The Floquet multipliers of the current orbit (ISP = 2 computes them) into
  ! PAR(12:23), real and imaginary parts in turn, for the multiplier k
  ! PAR(10 + 2k) and PAR(11 + 2k): named in ICP after the free parameters, AUTO
  ! prints them in the b-file with 11 digits (its d-file has 6).
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM
  DOUBLE PRECISION, INTENT(IN) :: U(NDIM)
  DOUBLE PRECISION, INTENT(INOUT) :: PAR(*)
  DOUBLE PRECISION, EXTERNAL :: GETP
  INTEGER I
  DO I = 1, 2*NDIM
     PAR(11 + I) = GETP('EIG', I, U)
  END DO
END SUBROUTINE PVLS
