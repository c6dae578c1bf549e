// The GeoScenario behavior-tree language (`.btree`, SPEC §8), as the reference implementation
// reads it: an indentation-based tree of composites and leaves.
//
//   behaviortree drive:
//       ?
//           ->
//               condition c_occ(lane_occupied(zid=FRONT, distance=30))
//               maneuver m_follow(MFollowConfig())
//           maneuver m_keep(MVelKeepConfig(vel=MP(14.0,10,6)))
//
// INDENT, DEDENT and CALL_OPEN are not produced by this lexer: compiler/gss/btree.cpp turns the
// NL tokens (which carry the next line's indentation) into INDENT and DEDENT, and a '(' right
// after a name into CALL_OPEN. So a name followed by '(' always opens a call, as in Python (the
// reference evaluates these arguments as Python): `MP(1,2,3)` and `MP (1,2,3)` are one value,
// never a name and a tuple, and every decision of the grammar needs at most two tokens of
// lookahead. (Deciding call-or-tuple by lookahead cost ANTLR seconds on calls nested a hundred
// deep: fuzz finding 34.) Arguments inside a call may be separated by commas or, as the
// reference tolerates, by spaces only.
grammar Btree;

tokens { INDENT, DEDENT, CALL_OPEN }

btreeFile : NL* treeDecl+ EOF ;
treeDecl  : BEHAVIORTREE NAME ':' NL INDENT node DEDENT ;
node      : composite | leaf ;
composite : op=(FALLBACK | SEQUENCE | PARALLEL) NL INDENT node+ DEDENT ;
leaf      : (condition | maneuver | subtree) NL ;
condition : CONDITION NAME CALL_OPEN call ')' ;
maneuver  : MANEUVER NAME CALL_OPEN call ')' ;
subtree   : SUBTREE NAME CALL_OPEN (item (','? item)*)? ')' ;
call      : NAME CALL_OPEN (item (','? item)*)? ')' ;
item      : (NAME '=')? value ;
value
    : call                                    # callValue
    | NUMBER                                  # numberValue
    | NAME                                    # nameValue
    | '(' value (',' value)* ')'              # tupleValue
    ;

BEHAVIORTREE : 'behaviortree' ;
CONDITION    : 'condition' ;
MANEUVER     : 'maneuver' ;
SUBTREE      : 'subtree' ;
FALLBACK     : '?' ;
SEQUENCE     : '->' ;
PARALLEL     : '||' ;
NUMBER       : [+-]? ([0-9]+ ('.' [0-9]*)? | '.' [0-9]+) ([eE] [+-]? [0-9]+)? ;
NAME         : [a-zA-Z_] [a-zA-Z_0-9]* ;
NL           : '\r'? '\n' [ \t]* ;
WS           : [ \t]+ -> skip ;
COMMENT      : '#' ~[\r\n]* -> skip ;
ANY          : . ;
