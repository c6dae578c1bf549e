// The .sdv language (docs/language.md is its reference). Keywords are contextual: every keyword
// may also be used as a name (see `ident`), so the language can grow without breaking files.
// Units after numbers are recognised by a predicate on the unit table, so an identifier after
// a number is a unit only when it is one ("40 m speed 13.9 m/s").
grammar Sdv;

@parser::header {
#include "compiler/syntax/unit_words.h"
}

file : item* EOF ;

item
    : importDecl
    | roadDecl
    | junctionDecl
    | mapDecl
    | treeDecl
    | scenarioDecl
    ;

importDecl : IMPORT STRING (AS ident)? ;

// ---------------------------------------------------------------- roads and maps
roadDecl : ROAD ident '{' roadStmt* '}' ;
roadStmt
    : LANES laneCount (',' laneCount)*                    # roadLanes
    | LANE_WIDTH value                                    # roadLaneWidth
    | SPEED_LIMIT value                                   # roadSpeedLimit
    | STRAIGHT value                                      # roadStraight
    | ARC value RADIUS value (LEFT | RIGHT)?              # roadArc
    | ORIGIN '(' value ',' value ')' (HEADING value)?     # roadOrigin
    | crosswalk                                           # roadCrosswalk
    ;
// A pedestrian crossing: on a road `at` a position along it, on a junction `on` an arm (`at`:
// its distance from the junction box).
crosswalk : CROSSWALK ident (ON ident)? (AT value)? (WIDTH value)? SIGNALISED? ;
laneCount : INT ident ;

junctionDecl : JUNCTION ident '{' junctionStmt* '}' ;
junctionStmt
    : LANES INT                                           # junctionLanes
    | LANE_WIDTH value                                    # junctionLaneWidth
    | SPEED_LIMIT value                                   # junctionSpeedLimit
    | ARM_LENGTH value                                    # junctionArmLength
    | CONTROL ident                                       # junctionControl
    | crosswalk                                           # junctionCrosswalk
    ;

mapDecl : MAP ident '{' mapStmt* '}' ;
mapStmt
    : FILE STRING                                         # mapFile
    | ORIGIN '(' value ',' value (',' value)? ')'         # mapOrigin
    ;

// ---------------------------------------------------------------- trees
treeDecl : TREE ident '(' (paramDecl (',' paramDecl)*)? ')' '{' node* '}' ;
paramDecl : ident ':' ident ('=' value)? ;

node : (ident ':')? nodeBody ;
nodeBody
    : compositeKind ('(' argList? ')')? '{' node* '}'     # compositeNode
    | CONDITION ident '(' argList? ')'                    # conditionNode
    | MANEUVER ident '(' argList? ')'                     # maneuverNode
    | SUBTREE qualName '(' argList? ')'                   # subtreeNode
    | decorator node                                      # decoratorNode
    ;
compositeKind : FALLBACK | SEQUENCE | REACTIVE_SEQUENCE | PARALLEL ;
decorator : NOT | ONCE | LATCH ;

argList : arg (',' arg)* ','? ;
arg : qualName '=' value ;

// ---------------------------------------------------------------- values
// A single value and an interval share their first primary, so they are one alternative: two
// would have the parser read to the end of that primary to choose.
value
    : primary (spread | DOTDOT primary)? samples?         # scalarValue
    | '[' (value (',' value)*)? ']'                       # listValue
    ;
spread : PLUSMINUS primary ;
samples : SAMPLES INT method? ;
method : ident ('(' value ')')? ;
primary
    : factor (op+=('+' | '-' | '*') factor | op+='/' divisor)*
    | STRING
    ;
// Arithmetic on quantities (`20 m + 25 m * i`, `(20 + 25*i) m`): a flat list of factors and
// operators (the builder applies precedence), so that a plain value costs the parser one rule
// more than before and a long sum does not nest. A unit after a closing parenthesis applies to
// the plain number inside. After `/` a name would read as a unit (`m/s`), so a divisor is a
// number or a parenthesis (`(100 / (i)) m`): the parser never needs more than two tokens to
// tell a unit from a quotient.
factor
    : quantity                                            # quantityFactor
    | sign='-'? qualName                                  # nameFactor
    | group                                               # groupFactor
    ;
divisor : quantity | group ;
group : sign='-'? '(' primary ')' unit? ;
quantity : sign=('-' | '+')? number unit? ;
number : INT | FLOAT ;
unit
    : PERCENT
    | unitAtom (('/' ident) | SUP2 | SUP3 | ('^' INT))*
    ;
unitAtom : {sdv::compiler::syntax::is_unit_word(_input->LT(1)->getText())}? ident ;

qualName : ident ('.' ident)* ;

// ---------------------------------------------------------------- scenarios
scenarioDecl : SCENARIO ident '{' scenarioStmt* '}' ;
scenarioStmt
    : ROAD qualName                                       # scenarioRoad
    | TIMEOUT value                                       # scenarioTimeout
    | SEED INT                                            # scenarioSeed
    | RATE ident value                                    # scenarioRate
    | (EGO | VEHICLE | PEDESTRIAN) ident repeat? ':' ident '{' vehicleStmt* '}'   # scenarioVehicle
    | OBJECT ident repeat? '{' vehicleStmt* '}'           # scenarioObject
    | LIGHT qualName '{' lightStmt* '}'                   # scenarioLight
    | EXPECT expr window?                                 # scenarioExpect
    | VARY '{' varyStmt* '}'                              # scenarioVary
    ;

// Many similar agents: `vehicle v[1..50]: sdv { ... }` declares v1 .. v50, the body evaluated
// with the index (`i`, or the name given: `v[k = 1..50]`) bound to each value.
repeat : '[' (ident '=')? primary DOTDOT primary ']' ;

// A campaign: the parameters a sweep varies and how it samples them (docs/campaigns.md).
varyStmt
    : qualName IN varyDomain                              # varyParam
    | SAMPLE ident INT?                                   # varySample
    | SEED INT                                            # varySeed
    ;
varyDomain
    : '[' primary (',' primary)* ']'                      # varySet
    | primary '..' primary (COUNT INT)?                   # varyRange
    | ident '(' primary ',' primary ')'                   # varyDistribution
    ;

vehicleStmt
    : START position                                      # vehStart
    | SPEED value                                         # vehSpeed
    | LENGTH value                                        # vehLength
    | WIDTH value                                         # vehWidth
    | GOAL position (ENDS RUN)?                           # vehGoal
    | ROUTE laneRef (',' laneRef)*                        # vehRoute
    | TREE qualName '(' argList? ')'                      # vehTree
    | TRAJECTORY '{' waypoint* '}'                        # vehTrajectory
    | PATH '{' pathPoint* '}'                             # vehPath
    | MEET ident                                          # vehMeet
    ;
position
    : laneRef AT value (OFFSET value)?                    # lanePosition
    | AT '(' value ',' value ')' (HEADING value)?         # xyPosition
    ;
laneRef : LANE (laneIndex | qualName | STRING) ;
laneIndex : sign='-'? INT ;
// A waypoint's time begins with a number or a parenthesis (`2 s`, `2 s + 500 ms`, `(i * 2) s`).
waypoint : time=leadPrimary ':' position (SPEED value)? ;
pathPoint : position (SPEED value)? ;

lightStmt
    : OFFSET value                                        # lightOffset
    | ident leadPrimary (spread | DOTDOT primary)? samples?   # lightPhase
    ;
// Where values follow one another without a separator, a trajectory's waypoints (`0 s: ...
// 2 s: ...`) and a light's phases (`green 20 s  yellow 3 s`), the value that starts each one
// begins with a number or a parenthesis (`2 s + 500 ms`, `(i * 2) s`), never with a sign or a
// name: `speed 5 m/s -1 s: ...` or `green 1 m  m + 1 m` would read as more of the value before
// it, and to tell, the parser would look ahead to the ':' or to the end of the phase at every
// term of every value of the file (fuzz finding 37: a sum of 6,400 terms, 51 KB, parsed in 3.4 s).
leadPrimary : leadFactor (op+=('+' | '-' | '*') factor | op+='/' divisor)* ;
leadFactor
    : number unit?                                        # leadQuantity
    | '(' primary ')' unit?                               # leadGroup
    ;

expr
    : NOT expr                                            # notExpr
    | expr AND expr                                       # andExpr
    | expr OR expr                                        # orExpr
    | '(' expr ')'                                        # parenExpr
    | call (cmp=('<' | '<=' | '>' | '>=') value)?         # callExpr
    ;
call : ident '(' (ident (',' ident)*)? ')' ;
// The time window of an expectation: `during 5 s .. 20 s`, `after 5 s`, `before 20 s`.
window : (DURING | AFTER | BEFORE) value ;

// Every keyword is also a valid name.
ident
    : ID | IMPORT | AS | ROAD | LANES | LANE_WIDTH | SPEED_LIMIT | STRAIGHT | ARC | RADIUS
    | ORIGIN | HEADING | JUNCTION | ARM_LENGTH | CONTROL | MAP | FILE | TREE | CONDITION
    | MANEUVER | SUBTREE | FALLBACK | SEQUENCE | REACTIVE_SEQUENCE | PARALLEL | NOT | ONCE | LATCH
    | SAMPLES | SCENARIO | TIMEOUT | SEED | RATE | EGO | VEHICLE | OBJECT | LIGHT | EXPECT
    | START | SPEED | LENGTH | WIDTH | GOAL | ROUTE | TRAJECTORY | AT | OFFSET | LANE | AND | OR
    | LEFT | RIGHT | ENDS | RUN | DURING | AFTER | BEFORE | VARY | IN | SAMPLE | COUNT
    | PEDESTRIAN | PATH | CROSSWALK | ON | SIGNALISED | MEET
    ;

// ---------------------------------------------------------------- lexer
IMPORT : 'import' ;
AS : 'as' ;
ROAD : 'road' ;
LANES : 'lanes' ;
LANE_WIDTH : 'lane_width' ;
SPEED_LIMIT : 'speed_limit' ;
STRAIGHT : 'straight' ;
ARC : 'arc' ;
RADIUS : 'radius' ;
ORIGIN : 'origin' ;
HEADING : 'heading' ;
JUNCTION : 'junction' ;
ARM_LENGTH : 'arm_length' ;
CONTROL : 'control' ;
MAP : 'map' ;
FILE : 'file' ;
TREE : 'tree' ;
CONDITION : 'condition' ;
MANEUVER : 'maneuver' ;
SUBTREE : 'subtree' ;
FALLBACK : 'fallback' ;
SEQUENCE : 'sequence' ;
REACTIVE_SEQUENCE : 'reactive_sequence' ;
PARALLEL : 'parallel' ;
NOT : 'not' ;
ONCE : 'once' ;
LATCH : 'latch' ;
SAMPLES : 'samples' ;
SCENARIO : 'scenario' ;
TIMEOUT : 'timeout' ;
SEED : 'seed' ;
RATE : 'rate' ;
EGO : 'ego' ;
VEHICLE : 'vehicle' ;
PEDESTRIAN : 'pedestrian' ;
PATH : 'path' ;
CROSSWALK : 'crosswalk' ;
ON : 'on' ;
SIGNALISED : 'signalised' ;
MEET : 'meet' ;
OBJECT : 'object' ;
LIGHT : 'light' ;
EXPECT : 'expect' ;
START : 'start' ;
SPEED : 'speed' ;
LENGTH : 'length' ;
WIDTH : 'width' ;
GOAL : 'goal' ;
ROUTE : 'route' ;
TRAJECTORY : 'trajectory' ;
AT : 'at' ;
OFFSET : 'offset' ;
LANE : 'lane' ;
AND : 'and' ;
OR : 'or' ;
LEFT : 'left' ;
RIGHT : 'right' ;
ENDS : 'ends' ;
RUN : 'run' ;
DURING : 'during' ;
AFTER : 'after' ;
BEFORE : 'before' ;
VARY : 'vary' ;
IN : 'in' ;
SAMPLE : 'sample' ;
COUNT : 'count' ;

PLUSMINUS : '±' | '+-' ;
SUP2 : '²' ;
SUP3 : '³' ;
PERCENT : '%' ;
DOTDOT : '..' ;
LE : '<=' ;
GE : '>=' ;
LT : '<' ;
GT : '>' ;

FLOAT : DIGITS '.' DIGITS EXPONENT? | DIGITS EXPONENT ;
INT : DIGITS ;
fragment DIGITS : [0-9] ('_'? [0-9])* ;
fragment EXPONENT : [eE] [+-]? [0-9]+ ;

ID : [a-zA-Z_] [a-zA-Z_0-9]* ;
STRING : '"' (~["\\\r\n] | '\\' ~[\r\n])* '"' ;
UNTERMINATED_STRING : '"' (~["\\\r\n] | '\\' ~[\r\n])* ;

COMMENT : '#' ~[\r\n]* -> channel(HIDDEN) ;
WS : [ \t\r\n\u000C]+ -> channel(HIDDEN) ;

// Anything else becomes one token the builder reports as "unexpected character".
ERROR_CHAR : . ;
