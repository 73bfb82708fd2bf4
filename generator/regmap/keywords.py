"""Reserved words of the languages regmap generates, shared by the front end (device ids) and the C back end."""

C_KEYWORDS = frozenset(
    [
        "auto",
        "break",
        "case",
        "char",
        "const",
        "continue",
        "default",
        "do",
        "double",
        "else",
        "enum",
        "extern",
        "float",
        "for",
        "goto",
        "if",
        "inline",
        "int",
        "long",
        "register",
        "restrict",
        "return",
        "short",
        "signed",
        "sizeof",
        "static",
        "struct",
        "switch",
        "typedef",
        "union",
        "unsigned",
        "void",
        "volatile",
        "while",
        "alignas",
        "alignof",
        "bool",
        "constexpr",
        "false",
        "nullptr",
        "static_assert",
        "thread_local",
        "true",
        "typeof",
        "typeof_unqual",
    ]
)
CPP_KEYWORDS = frozenset(
    [
        "and",
        "and_eq",
        "asm",
        "bitand",
        "bitor",
        "catch",
        "char8_t",
        "char16_t",
        "char32_t",
        "class",
        "co_await",
        "co_return",
        "co_yield",
        "compl",
        "concept",
        "const_cast",
        "consteval",
        "constinit",
        "decltype",
        "delete",
        "dynamic_cast",
        "explicit",
        "export",
        "friend",
        "mutable",
        "namespace",
        "new",
        "noexcept",
        "not",
        "not_eq",
        "operator",
        "or",
        "or_eq",
        "private",
        "protected",
        "public",
        "reinterpret_cast",
        "requires",
        "static_cast",
        "template",
        "this",
        "throw",
        "try",
        "typeid",
        "typename",
        "using",
        "virtual",
        "wchar_t",
        "xor",
        "xor_eq",
    ]
)

# IEC 61131-3 (editions 2 and 3) reserved words, the elementary type names and the standard
# functions, plus the CODESYS / TwinCAT additions: a Structured Text name must be none of them
# (compared case-insensitively, as ST compares every identifier).
IEC_KEYWORDS = frozenset(
    """
    ABSTRACT ACTION AND ARRAY AT BY CASE CLASS CONFIGURATION CONSTANT CONTINUE DO ELSE ELSIF END_ACTION
    END_CASE END_CLASS END_CONFIGURATION END_FOR END_FUNCTION END_FUNCTION_BLOCK END_IF END_INTERFACE
    END_METHOD END_NAMESPACE END_PROGRAM END_PROPERTY END_REPEAT END_RESOURCE END_STEP END_STRUCT
    END_TRANSITION END_TYPE END_UNION END_VAR END_WHILE EN ENO EXIT EXTENDS F_EDGE FALSE FINAL FOR FROM
    FUNCTION FUNCTION_BLOCK IF IMPLEMENTS INITIAL_STEP INTERFACE INTERNAL JMP METHOD MOD NAMESPACE NON_RETAIN
    NOT NULL OF ON OR OVERLAP OVERRIDE PRIORITY PRIVATE PROGRAM PROPERTY PROTECTED PUBLIC READ_ONLY READ_WRITE
    REF REF_TO REPEAT RESOURCE RETAIN RETURN R_EDGE SINGLE STEP STRUCT SUPER TASK THEN THIS TO TRANSITION
    TRUE TYPE UNION UNTIL USING VAR VAR_ACCESS VAR_CONFIG VAR_EXTERNAL VAR_GLOBAL VAR_IN_OUT VAR_INPUT
    VAR_INST VAR_OUTPUT VAR_STAT VAR_TEMP WHILE WITH XOR
    BOOL BYTE WORD DWORD LWORD SINT INT DINT LINT USINT UINT UDINT ULINT REAL LREAL TIME LTIME DATE LDATE
    TIME_OF_DAY TOD LTOD DATE_AND_TIME DT LDT STRING WSTRING CHAR WCHAR ANY ANY_NUM ANY_INT ANY_REAL ANY_BIT
    ANY_DATE ANY_STRING ANY_DERIVED ANY_ELEMENTARY ANY_MAGNITUDE ANY_SIGNED ANY_UNSIGNED ANY_DURATION
    ANY_CHARS ANY_CHAR POINTER REFERENCE BIT XWORD UXINT XINT __NEW __DELETE __QUERYINTERFACE
    ABS SQRT LN LOG EXP SIN COS TAN ASIN ACOS ATAN ATAN2 ADD SUB MUL DIV EXPT MOVE SHL SHR ROL ROR SEL MAX
    MIN LIMIT MUX GT GE EQ LE LT NE LEN LEFT RIGHT MID CONCAT INSERT DELETE REPLACE FIND TRUNC ADR ADRINST
    BITADR SIZEOF INDEXOF UPPER_BOUND LOWER_BOUND TEST_AND_SET CAL CALC CALCN RET RETC RETCN JMPC JMPCN
    LD LDN ST STN S R ANDN ORN XORN NOT_ CONT
    """.split()
)
