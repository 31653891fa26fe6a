!----------------------------------------------------------------------
! Jeffcott rotor in the rotating frame: unit mass on a shaft of unit stiffness
! with cubic hardening BETA, rotating (internal) damping c_int, stationary
! (external) damping c_ext, eccentricity ecc, constant speed Om. In the fixed
! frame, with z = x + i y,
!
!   z'' + c_ext z' + c_int (z' - i Om z) + (1 + BETA |z|**2) z = ecc Om**2 exp(i Om t),
!
! and with z = (u1 + i u2) exp(i Om t), v = u', the autonomous rotating-frame field
!
!   u1' = v1,  u2' = v2,
!   v1' = -(c_ext + c_int) v1 + 2 Om v2 + s u1 + c_ext Om u2 + ecc Om**2,
!   v2' = -(c_ext + c_int) v2 - 2 Om v1 + s u2 - c_ext Om u1,
!   s = Om**2 - 1 - BETA (u1**2 + u2**2).
!
! Its equilibrium (synchronous whirl) loses stability at a Hopf point; for
! ecc = 0 (or BETA = 0) at Om = 1 + c_ext / c_int exactly.
!
! U = (u1, u2, v1, v2); PAR(1) = Om, PAR(2) = c_ext, PAR(3) = c_int,
! PAR(4) = BETA, PAR(5) = ecc. Jacobians by hand (JAC = 1).
!----------------------------------------------------------------------
SUBROUTINE FUNC(NDIM,U,ICP,PAR,IJAC,F,DFDU,DFDP)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM, ICP(*), IJAC
  DOUBLE PRECISION, INTENT(IN) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(OUT) :: F(NDIM)
  DOUBLE PRECISION, INTENT(INOUT) :: DFDU(NDIM,NDIM), DFDP(NDIM,*)
  DOUBLE PRECISION U1, U2, V1, V2, OM, CE, CI, BETA, ECC, R2, S, CT

  U1 = U(1)
  U2 = U(2)
  V1 = U(3)
  V2 = U(4)
  OM = PAR(1)
  CE = PAR(2)
  CI = PAR(3)
  BETA = PAR(4)
  ECC = PAR(5)
  R2 = U1*U1 + U2*U2
  S = OM*OM - 1.0D0 - BETA*R2
  CT = CE + CI
  F(1) = V1
  F(2) = V2
  F(3) = -CT*V1 + 2*OM*V2 + S*U1 + CE*OM*U2 + ECC*OM*OM
  F(4) = -CT*V2 - 2*OM*V1 + S*U2 - CE*OM*U1
  IF (IJAC == 0) RETURN

  DFDU(:,:) = 0.0D0
  DFDU(1,3) = 1.0D0
  DFDU(2,4) = 1.0D0
  DFDU(3,1) = S - 2*BETA*U1*U1
  DFDU(3,2) = -2*BETA*U1*U2 + CE*OM
  DFDU(3,3) = -CT
  DFDU(3,4) = 2*OM
  DFDU(4,1) = -2*BETA*U1*U2 - CE*OM
  DFDU(4,2) = S - 2*BETA*U2*U2
  DFDU(4,3) = -2*OM
  DFDU(4,4) = -CT
  IF (IJAC == 1) RETURN

  DFDP(1:2,1:5) = 0.0D0
  DFDP(3,1) = 2*V2 + 2*OM*U1 + CE*U2 + 2*ECC*OM
  DFDP(4,1) = -2*V1 + 2*OM*U2 - CE*U1
  DFDP(3,2) = -V1 + OM*U2
  DFDP(4,2) = -V2 - OM*U1
  DFDP(3,3) = -V1
  DFDP(4,3) = -V2
  DFDP(3,4) = -R2*U1
  DFDP(4,4) = -R2*U2
  DFDP(3,5) = OM*OM
  DFDP(4,5) = 0.0D0
END SUBROUTINE FUNC

SUBROUTINE STPNT(NDIM,U,PAR,T)
  ! At rest: at Om = 0 the rotor on the axis is the equilibrium (PAR from the constants).
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM
  DOUBLE PRECISION, INTENT(INOUT) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(IN) :: T
  U(1:NDIM) = 0.0D0
END SUBROUTINE STPNT

SUBROUTINE BCND
END SUBROUTINE BCND

SUBROUTINE ICND
END SUBROUTINE ICND

SUBROUTINE FOPT
END SUBROUTINE FOPT

SUBROUTINE PVLS
END SUBROUTINE PVLS
