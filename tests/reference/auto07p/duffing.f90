!----------------------------------------------------------------------
! Forced Duffing oscillator, one-harmonic balance (the `duffing` residual of
! tests/analysis/test_continuation.py):
!
!   x'' + C x' + W0**2 x + BETA x**3 = f cos(om t),   x = p cos(om t) + q sin(om t),
!
!   (W0**2 - om**2) p + C om q + 3/4 BETA (p**2 + q**2) p - f = 0,
!   (W0**2 - om**2) q - C om p + 3/4 BETA (p**2 + q**2) q     = 0.
!
! U = (p, q); PAR(1) = om (forcing frequency), PAR(2) = f (forcing amplitude),
! PAR(3) = W0, PAR(4) = C, PAR(5) = BETA (fixed; set from the constants, so that the
! Python side is the one place that states them).
! Jacobians by hand (JAC = 1): AUTO's fold continuation puts F_u in its
! extended system, so finite-difference Jacobians would cost accuracy.
!----------------------------------------------------------------------
SUBROUTINE FUNC(NDIM,U,ICP,PAR,IJAC,F,DFDU,DFDP)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM, ICP(*), IJAC
  DOUBLE PRECISION, INTENT(IN) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(OUT) :: F(NDIM)
  DOUBLE PRECISION, INTENT(INOUT) :: DFDU(NDIM,NDIM), DFDP(NDIM,*)
  DOUBLE PRECISION P, Q, OM, FF, W0, C, BETA, A, D, G

  P = U(1)
  Q = U(2)
  OM = PAR(1)
  FF = PAR(2)
  W0 = PAR(3)
  C = PAR(4)
  BETA = PAR(5)
  A = P*P + Q*Q
  D = W0**2 - OM**2
  G = 0.75D0*BETA
  F(1) = D*P + C*OM*Q + G*A*P - FF
  F(2) = D*Q - C*OM*P + G*A*Q
  IF (IJAC == 0) RETURN

  DFDU(1,1) = D + G*(A + 2*P*P)
  DFDU(1,2) = C*OM + 2*G*P*Q
  DFDU(2,1) = -C*OM + 2*G*P*Q
  DFDU(2,2) = D + G*(A + 2*Q*Q)
  IF (IJAC == 1) RETURN

  DFDP(1,1) = -2*OM*P + C*Q
  DFDP(2,1) = -2*OM*Q - C*P
  DFDP(1,2) = -1.0D0
  DFDP(2,2) = 0.0D0
  DFDP(1,3) = 2*W0*P
  DFDP(2,3) = 2*W0*Q
  DFDP(1,4) = OM*Q
  DFDP(2,4) = -OM*P
  DFDP(1,5) = 0.75D0*A*P
  DFDP(2,5) = 0.75D0*A*Q
END SUBROUTINE FUNC

SUBROUTINE STPNT(NDIM,U,PAR,T)
  ! The start (PAR and U) comes from the constants: the driver passes a solution
  ! converged to machine precision, since AUTO takes the first point as given.
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

SUBROUTINE PVLS
END SUBROUTINE PVLS
