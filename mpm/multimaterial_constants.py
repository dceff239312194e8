"""Integer codes and array slots shared by the multimaterial tables and kernels.

Kept in one small module so the numba kernels (which read them as global
constants, frozen at compile time) and the Python table builder agree.
"""
from __future__ import annotations

# --- law_kind[M, M] codes -------------------------------------------------
LAW_NONE = 0
"""No interaction: the two velocity fields ignore each other."""
LAW_PERFECT = 1
"""Perfect bond: both fields always move with the centre-of-mass velocity."""
LAW_STICK = 2
"""Stick contact: centre-of-mass velocity only while approaching and touching."""
LAW_FRICTION = 3
"""Coulomb friction contact (mu in law_params[..., P_MU]; mu = 0 is frictionless)."""
LAW_IMPERFECT = 4
"""Imperfect interface (000 Eq 17, 002 Eq 37-39): Dn in tension, Dn in
compression (bilinear when they differ), Dt; math.inf marks a perfect direction."""

# --- law_params[M, M, N_PARAMS] slots --------------------------------------
P_DN_TENSION = 0
P_DT = 1
P_DN_COMPRESSION = 2
P_MU = 3
N_PARAMS = 4

# --- settings[N_SETTINGS] slots --------------------------------------------
S_NORMAL = 0            # NORMAL_* code
S_SEPARATION = 1        # SEP_* code
S_AREA_CORRECTION = 2   # 1.0 = 000 Eq 20, 0.0 = A_i = Omega_i / h
S_HPERP = 3             # HPERP_* code (000 Eq 21-22)
S_FORCE_LIMIT = 4       # 1.0 = limit interface forces (000 Eq 23-27)
S_EDGE_CUTOFF = 5       # screen nodes with Omega_i < cutoff * cell volume
S_CONTACT_OFFSET = 6    # delta_con = factor * h (000 Eq 14, 004 Eq 16-17)
S_MASS_TOL = 7          # a field is present at a node if m > tol * m_total
S_LUMP_CONSERVE = 8     # 1.0 = restore momentum balance on 3+ nodes
S_SN_X = 9              # specified normal (SN), from lower to higher body index
S_SN_Y = 10
S_SN_Z = 11
S_DF_S0 = 12            # DF separation: s of the first tabulated d(s) value (cells)
S_DF_DS = 13            # ... and the spacing of the table (cells)
S_THREE_MATERIAL = 14   # THREE_* code: how nodes seen by 3+ materials are corrected
N_SETTINGS = 15

# --- nodes seen by three or more materials (004 Sec 3.4) ----------------------
THREE_LUMP = 0          # each material against the lump of the others (004 Eq 50)
THREE_EXPLICIT = 1      # the pairs in contact per pair, 1-2 pairs solved simultaneously (Eq 49)
THREE_MATERIAL_CODES = {"lump": THREE_LUMP, "explicit": THREE_EXPLICIT}

# --- normal methods (000 Sec 2.5, 004 Eq 13, 004 Sec 3.1) -------------------
NORMAL_SN = 0
NORMAL_MVG = 1
NORMAL_AVG = 2
NORMAL_RMVG = 3
NORMAL_LR = 4
NORMAL_AG = 5
NORMAL_SN_RADIAL = 6    # SN about a centre (option normal_center): per-node normals
NORMAL_CODES = {"SN": NORMAL_SN, "MVG": NORMAL_MVG, "AVG": NORMAL_AVG,
                "RMVG": NORMAL_RMVG, "LR": NORMAL_LR, "AG": NORMAL_AG}

# --- separation methods (000 Eq 13-14, 004 Eq 15, 24) ---------------------------
SEP_DISPLACEMENT = 0
SEP_OFFSET = 1
SEP_LR = 2
SEP_DF = 3              # edge distances d(x) of 004 Eq 15 (mpm/contact_separation.py)
SEP_VELOCITY = 4        # no separation test: contact whenever approaching (004 Eq 14 alone)
SEPARATION_CODES = {"displacement": SEP_DISPLACEMENT, "offset": SEP_OFFSET, "LR": SEP_LR, "DF": SEP_DF,
                    "velocity": SEP_VELOCITY}

# --- h-perp methods (000 Eq 21-22) -----------------------------------------
HPERP_NONE = 0          # h = dx (no tilt correction)
HPERP_TANGENT = 1       # method 1 of 000 (Eq 22), recommended by the paper
HPERP_NORMAL = 2        # method 2 of 000: distance to the cell ellipsoid along n
HPERP_CODES = {"none": HPERP_NONE, "ellipse_tangent": HPERP_TANGENT, "eq22": HPERP_TANGENT,
               "ellipse_normal": HPERP_NORMAL}

# --- node_out[N, NODE_OUT_COLUMNS] columns (add_interface_forces) -----------
OUT_JUMP_N = 0          # [u_n] = delta . n (mm)
OUT_JUMP_T = 1          # [u_t]: signed along t = (-n_y, n_x) in 2D, magnitude in 3D (mm)
OUT_TRACTION_N = 2      # T_n (MPa), force-limited value if limited
OUT_TRACTION_T = 3      # T_t (MPa), same sign convention as OUT_JUMP_T
OUT_NX = 4
OUT_NY = 5
OUT_NZ = 6
OUT_AREA = 7            # A_i (mm^2)
OUT_ENERGY = 8          # U_i (N mm), ERRATA 10
OUT_STATUS = 9          # STATUS_* bit flags
NODE_OUT_COLUMNS = 10

STATUS_INTERFACE = 1.0      # interface force evaluated at this node
STATUS_LIMITED_N = 2.0      # normal force capped by 000 Eq 26 (perfect this step)
STATUS_LIMITED_T = 4.0      # tangential force capped by 000 Eq 26
STATUS_SCREENED = 8.0       # edge node skipped (000 Sec 3, Omega_i < cutoff)
STATUS_CONTACT = 16.0       # normal closed (compression branch / contact)
STATUS_OVER_LIMIT = 32.0    # force_limiting off and the force exceeded 000 Eq 26 (unstable)
